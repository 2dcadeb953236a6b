// The memory plan's parts (memory_plan.cpp puts them together): the split of a scene's particles
// over the slabs as the engine makes it at the start (memory_split.cpp), and every buffer of one
// slab sized by the rules the allocations use (memory_buffers.cpp, through device/sizing.hpp).
// Pure C++.
#pragma once
#include "clsph/memory_plan.hpp"
#include "device/grid.hpp"
#include "device/memory_census.hpp"

#include <cstddef>
#include <vector>

namespace clsph::detail {

// The grid the engine makes for the scene (Simulation's set-up).
device::Grid grid_of(const Scene& scene);

// What one slab holds, in particles, at the start (several slabs: an estimate of the split).
struct Share {
    std::size_t owned = 0, active = 0, capacity = 0, cells = 0;
    std::size_t window = 0, outbox = 0, inbox = 0, columns = 0;
    std::size_t edge = 0;  // the most particles an edge sort sorts (0: the merges sort everything)
    // Growths of the store that keep its particles (the exchanges'): capacity before and after, and
    // the edge sort's particles then.
    struct Growth {
        std::size_t from, to, edge;
        std::size_t sorted;  // the particles the cell sort has sorted by then (its temporaries' size)
        bool tables, inbox;  // whether the cell tables and the exchange inbox exist by then
    };
    std::vector<Growth> kept_growths;
};

// The shares of `slabs` slabs (multi/slab_driver.cpp set_up(), multi/exchange.cpp).
std::vector<Share> split_shares(const Scene& scene, const MemoryCensus& census, std::size_t slabs,
                                const Options& options,
                                bool edges_apart);

// The plan of `devices` (one entry per slab) for their shares.
MemoryPlan plan_slabs(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                      const Options& options);

}  // namespace clsph::detail
