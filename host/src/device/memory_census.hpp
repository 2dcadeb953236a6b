// What the memory model (clsph/memory_plan.hpp) needs to know of a scene's particles, from the
// particles themselves or, without building them, from the lattice plan the devices generate from
// (set-up on the device: a billion particles are never on the host).
#pragma once
#include "clsph/memory_plan.hpp"
#include "clsph/particles.hpp"
#include "scene/lattice_plan.hpp"

#include <cstdint>
#include <vector>

namespace clsph::detail {

struct MemoryCensus {
    std::size_t particles = 0;
    std::vector<std::size_t> per_column;        // particles per grid column (split axis), in the domain
    std::vector<std::size_t> boundary_per_column;  // of which boundary particles (the balancer's work weights)
    std::vector<std::size_t> cells_per_column;  // non-empty cells per column
    std::uint32_t max_boundary_id = 0;
    bool any_boundary = false;
};

MemoryCensus census_of(const Scene& scene, const Particles& p);
MemoryCensus census_of(const Scene& scene, const scene::LatticePlan& plan);
MemoryPlan plan_memory(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                       const Options& options);

}  // namespace clsph::detail
