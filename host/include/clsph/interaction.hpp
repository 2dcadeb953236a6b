// The forms of the interaction pass (the neighbour loop under the force and summation-density
// kernels). Every form computes the same physics, summing each particle's neighbour terms in the
// same order (rows in turn, neighbours in increasing index), so results differ only by round-off.
#pragma once
#include <string>
#include <vector>

namespace clsph {

enum class Interaction {
    automatic,  // per device: lanes on CPUs through pocl, fine on GPUs and Mesa rusticl
    fine,       // a work-item per particle, every candidate tested and summed in turn
    lanes,      // a work-item per cell, its particles in 8 or 16 vector lanes (the CPU form)
    coarse,     // a work-group per cell, neighbour rows staged in local memory (the paper's scheme)
    clusters,   // a work-item per particle, candidates from cluster-pair lists (docs/interaction.md)
};

// "auto", "fine", "lanes", "coarse", "clusters".
const char* interaction_name(Interaction form);
// The inverse; throws clsph::Error listing the names for anything else.
Interaction interaction_from_name(const std::string& name);
// Every concrete form (not automatic), in the order above.
std::vector<Interaction> interaction_forms();

}  // namespace clsph
