// The step's end in the slab driver (multi/slab_driver.hpp): the kick's reductions over every
// device and rank, and the inlets' particles due (scene/open_boundaries.hpp), which every host
// makes alike.
#include "multi/slab_driver.hpp"

#include <algorithm>

namespace clsph::multi {

StepOutcome SlabDriver::reductions(cl_rt::EventSet& kicked) {
    {
        PhaseTimer t(phases_, "forces and kick");
        kicked.wait("the second kick", options_.wait);
    }
    StepOutcome out;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (!here(d) || slabs_[d].store->ranges.owned == 0) continue;
        const auto k = slabs_[d].physics->kick_result();
        out.kick.max_speed2 = std::max(out.kick.max_speed2, k.max_speed2);
        out.kick.max_accel2 = std::max(out.kick.max_accel2, k.max_accel2);
        out.kick.kinetic_energy += k.kinetic_energy;
        out.kick.fluid += k.fluid;
        if (k.bad_index >= 0 && out.kick.bad_index < 0) {
            out.kick.bad_index = k.bad_index;
            out.bad_slab = d;
        }
    }
    if (across_ranks()) {
        // Maxima, sums, and the first slab with a bad value (its index there) over every rank.
        std::vector<double> m{out.kick.max_speed2, out.kick.max_accel2};
        ranks_.ranks->max(m);
        std::vector<double> sums{out.kick.kinetic_energy};
        ranks_.ranks->sum(sums);
        const std::size_t D = slabs_.size();
        std::vector<std::uint64_t> counts(1 + 2 * D, 0);
        counts[0] = static_cast<std::uint64_t>(out.kick.fluid);
        if (out.kick.bad_index >= 0) {
            counts[1 + 2 * out.bad_slab] = 1;
            counts[2 + 2 * out.bad_slab] = static_cast<std::uint64_t>(out.kick.bad_index);
        }
        ranks_.ranks->sum(counts);
        out.kick.max_speed2 = m[0];
        out.kick.max_accel2 = m[1];
        out.kick.kinetic_energy = sums[0];
        out.kick.fluid = static_cast<decltype(out.kick.fluid)>(counts[0]);
        out.kick.bad_index = -1;
        for (std::size_t d = 0; d < D; ++d)
            if (counts[1 + 2 * d]) {
                out.kick.bad_index = static_cast<decltype(out.kick.bad_index)>(counts[2 + 2 * d]);
                out.bad_slab = d;
                break;
            }
    }
    return out;
}

const Particles* SlabDriver::created_by(double time) {
    if (feed_.empty()) return nullptr;
    created_ = feed_.due(time);
    return created_.size() > 0 ? &created_ : nullptr;
}

}  // namespace clsph::multi
