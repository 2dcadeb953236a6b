// Set-up on the device (kernels/generate.cl): each device writes the particles of its own slab of
// a scene made of lattice pieces (scene/lattice_plan.hpp) straight into its particle store, with
// the ids, positions and densities the host generator gives them. The host uploads only per-axis
// tables (kilobytes to a few megabytes), never the particles.
#pragma once
#include "cl/device.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/primitives.hpp"
#include "scene/lattice_plan.hpp"

#include <cstdint>
#include <vector>

namespace clsph::device {

// The planes of a piece that a slab of columns [first_col, end_col) holds: [first, end). Planes
// outside the domain below its first column go to the slab that starts at column 0, those above
// its last to the slab that ends at the last column (the first sort removes and counts them).
struct PlaneRange {
    std::size_t first = 0, end = 0;
};
PlaneRange planes_of(const scene::LatticePiece& piece, const Grid& grid, std::size_t first_col, std::size_t end_col);

// Particles a slab of columns [first_col, end_col) holds, per piece (known before generating:
// the plan counts every plane).
std::vector<std::uint64_t> slab_counts(const scene::LatticePlan& plan, const Grid& grid, std::size_t first_col,
                                       std::size_t end_col);

// The host's twin: the same slab's particles from the plan, in the order the device writes them.
Particles slab_particles(const scene::LatticePlan& plan, const Grid& grid, std::size_t first_col, std::size_t end_col);

class Generator {
public:
    Generator(cl_rt::Device& device, const Grid& grid);
    // Writes the slab's particles into `store` (grown to hold them; ranges: all owned, none sorted
    // yet, as after an upload) and returns how many. Checks each fluid piece's count against the plan.
    std::size_t generate(const scene::LatticePlan& plan, ParticleStore& store, std::size_t first_col, std::size_t end_col);

private:
    cl_rt::Device& device_;
    const Grid& grid_;
    Scan scan_;
    cl::Kernel boundary_k_, flags_k_, write_k_;
    std::size_t wg_;
};

}  // namespace clsph::device
