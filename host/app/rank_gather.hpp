// Across MPI ranks, what rank 0 writes for all of them: every rank's particles gathered to rank 0
// in rank order (so in slab order: rank 0's slabs come first along the split axis), the frame one
// process on as many devices holds.
#pragma once
#include <clsph/particles.hpp>
#include <clsph/ranks.hpp>

namespace clsph::app {

// Collective. On rank 0: every rank's `mine`, one after the other in rank order; elsewhere empty.
Particles gather_particles_to_rank0(Ranks& ranks, const Particles& mine);

}  // namespace clsph::app
