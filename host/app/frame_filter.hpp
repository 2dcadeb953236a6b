// Which particles a frame holds (--output-stride K, --output-box): every K-th particle by id, and
// only those inside a box, for runs too large to write whole. Frames and their CSV twins alike;
// never checkpoints or last_good.vtu, which must hold every particle to go on from.
#pragma once
#include <clsph/io.hpp>
#include <clsph/particles.hpp>
#include <clsph/simulation.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace clsph::app {

struct FrameFilter {
    std::size_t stride = 1;                             // keep ids divisible by it
    std::optional<std::array<double, 6>> box;           // xmin ymin zmin xmax ymax zmax, inclusive
    FrameFields fields;                                 // the point-data arrays written (--fields)

    // From the options' values; throws clsph::Error naming the option when one is unusable.
    static FrameFilter from_options(std::size_t stride, const std::vector<double>& box, const std::string& fields = "all");
    bool keeps_all() const { return stride == 1 && !box; }
    // What the devices select for a frame, so only its particles come to the host.
    ParticleSelection device_selection() const;
    bool keeps(std::uint32_t id, const std::array<double, 3>& x) const;
    Particles apply(Particles p) const;
};

}  // namespace clsph::app
