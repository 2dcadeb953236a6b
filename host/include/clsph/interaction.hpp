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

// The order of the particles within each cell, which is the order the interaction pass meets its
// candidates in (docs/interaction.md, "The order within cells"). Cells are always in key order;
// within a cell the particles keep their previous order (arrival), or are sorted along a Morton
// curve over 64 sub-cells (morton), so that runs of consecutive particles are compact. Results
// differ by round-off between the two (sums in another order); each is bitwise the same on any
// number of devices.
enum class CellOrder {
    automatic,  // morton where every device runs lanes (the form it speeds up), else arrival
    arrival,
    morton,
};
// "auto", "arrival", "morton".
const char* cell_order_name(CellOrder order);
// The inverse; throws clsph::Error listing the names for anything else.
CellOrder cell_order_from_name(const std::string& name);

}  // namespace clsph
