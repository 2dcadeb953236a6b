// A frame of every K-th particle by id (clsph run --output-stride), or of a box (--output-box),
// without downloading the rest:
// the particles are selected and packed on the device (kernels/select.cl) and only they are read,
// so a strided frame of a billion particles costs its own size, not the whole state. The flags and
// their scan use the store's reorder scratch (free between steps), the packed arrays are the
// frame's size.
#pragma once
#include "cl/device.hpp"
#include "clsph/particles.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/primitives.hpp"

#include <array>
#include <cstdint>
#include <optional>

namespace clsph::device {

class ThinDownload {
public:
    ThinDownload(cl_rt::Device& device, const Grid& grid);
    // The owned particles of `store` whose id is divisible by `stride` and, with a box (xmin ymin
    // zmin xmax ymax zmax, faces included), inside it, in the store's order; pressure left at 0
    // (as ParticleStore::download()). The device keeps the cells the box meets; the host the box.
    Particles download(ParticleStore& store, std::uint32_t stride, const std::optional<std::array<double, 6>>& box = {});

private:
    cl_rt::Device& device_;
    const Grid& grid_;
    Scan scan_;
    cl::Kernel flags_k_, gather_k_;
    std::size_t wg_;
};

}  // namespace clsph::device
