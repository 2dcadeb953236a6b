// The memory plan's split (device/memory_model.hpp): what each slab holds at the start and where
// its store grows keeping its particles, as multi/slab_driver.cpp and multi/exchange.cpp make them.
#include "device/memory_model.hpp"

#include "balance/balancer.hpp"
#include "device/sizing.hpp"
#include "scene/open_boundaries.hpp"

#include <algorithm>
#include <cstdint>

namespace clsph::detail {

std::vector<Share> split_shares(const Scene& scene, const MemoryCensus& census, std::size_t slabs,
                                const Options& options, bool edges_apart) {
    const std::size_t D = std::max<std::size_t>(slabs, 1);
    const std::size_t columns = grid_of(scene).params().n_s;
    const auto& per_column = census.per_column;
    const std::size_t total = census.particles;
    auto cells_in = [&](std::size_t c0, std::size_t c1) {
        std::size_t n = 0;
        for (std::size_t c = c0; c < std::min(c1, columns); ++c) n += census.cells_per_column[c];
        return n;
    };
    auto in_columns = [&](std::size_t c0, std::size_t c1) {
        std::size_t n = 0;
        for (std::size_t c = c0; c < std::min(c1, columns); ++c) n += per_column[c];
        return n;
    };

    // The split (multi/slab_driver.cpp set_up): one slab holds every particle; several, the
    // balancer's first cuts over the census profile (multi/partition.cpp census(): work 1 per fluid
    // particle, balance::default_boundary_weight per boundary one), as the engine places them for
    // --balance static and off, and for dynamic when no calibration has timed the devices.
    std::vector<Share> shares(D);
    std::vector<std::size_t> cuts{0, columns};
    std::size_t inside = 0;
    for (auto n : per_column) inside += n;
    if (D > 1) {
        balance::Options bo;
        bo.mode = options.balance == BalanceMode::dynamic ? balance::Mode::dynamic
                  : options.balance == BalanceMode::fixed ? balance::Mode::static_
                                                          : balance::Mode::off;
        bo.allow_idle = true;
        balance::ColumnProfile profile;
        profile.work.assign(columns, 0.0);
        profile.particles.assign(columns, 0);
        for (std::size_t c = 0; c < columns && c < per_column.size(); ++c) {
            const std::size_t boundary = c < census.boundary_per_column.size() ? census.boundary_per_column[c] : 0;
            profile.particles[c] = per_column[c];
            profile.work[c] = static_cast<double>(per_column[c] - boundary) +
                              static_cast<double>(boundary) * balance::default_boundary_weight;
        }
        cuts = balance::Balancer(D, columns, bo).initial_cuts(profile);
    }
    // Inlets: the first exchange takes their buffers into the inboxes of the slabs needing their
    // columns (multi/exchange.cpp), per column as the feed makes them (scene/open_boundaries.hpp).
    std::vector<std::size_t> buffer_per_column(columns, 0);
    if (!scene.inlets.empty()) {
        const device::Grid grid = grid_of(scene);
        const Particles buffer = scene::InletFeed(scene, 0).due(0.0);
        for (const auto& x : buffer.position) {
            std::array<float, 3> off{};
            const std::uint32_t key = grid.locate(x, off);
            if (key != grid.params().invalid_key) ++buffer_per_column[grid.cell_of_key(key)[0]];
        }
    }
    auto buffer_in = [&](std::size_t c0, std::size_t c1) {
        std::size_t n = 0;
        for (std::size_t c = c0; c < std::min(c1, columns); ++c) n += buffer_per_column[c];
        return n;
    };
    const double headroom = options.capacity_headroom;
    for (std::size_t d = 0; d < D; ++d) {
        Share& s = shares[d];
        const std::size_t first = cuts[d], end = cuts[d + 1];
        s.columns = end - first;
        // A store too small grows (sizing::grown_capacity); at the upload or the generation nothing
        // is kept: the old arrays go first, one allocation.
        // With inlets the count grows: planned for what they may add (scene/open_boundaries.hpp).
        s.capacity = device::sizing::slab_capacity(static_cast<std::size_t>(scene::planned_with_inlets(scene, total)), D, headroom);
        if (D == 1) {
            s.owned = total;
            s.active = in_columns(0, columns);
            s.cells = cells_in(0, columns);
            s.outbox = device::sizing::box_capacity(0);  // the boxes exist on one slab too
            s.inbox = device::sizing::box_capacity(buffer_in(0, columns));
            continue;
        }
        // partition.cpp split(): particles outside the domain go to slab 0 with the host's upload.
        s.owned = in_columns(first, end) + (d == 0 && total > inside ? total - inside : 0);
        Share::Growth at{};  // where a growth keeping the particles happens
        auto grow = [&](std::size_t n, bool keep) {
            if (n <= s.capacity) return;
            const std::size_t cap = device::sizing::grown_capacity(n, headroom);
            if (keep) {
                at.from = s.capacity, at.to = cap, at.edge = s.edge;
                s.kept_growths.push_back(at);
            }
            s.capacity = cap;
        };
        grow(s.owned, false);  // the upload or the generation: nothing kept
        if (s.columns == 0) {  // an idle slab (the balancer's idle_empty_slabs): no ghosts, no edges
            s.outbox = s.inbox = device::sizing::box_capacity(0);
            continue;
        }
        // Ghosts: one column either side (partition.cpp needs()).
        const std::size_t g0 = first > 0 ? first - 1 : 0, g1 = std::min(end + 1, columns);
        s.active = in_columns(g0, g1);
        s.cells = cells_in(g0, g1);
        // exchange.cpp: windows of two columns at each edge with a neighbour go out; the neighbours'
        // edge columns come in (the ghosts).
        std::size_t out = 0, arrivals_left = 0, arrivals_right = 0;
        if (d > 0) {
            s.window = std::max(s.window, in_columns(first, std::min(first + 2, end)));
            out += in_columns(first, std::min(first + 2, end));
            arrivals_left = in_columns(g0, first);
        }
        if (d + 1 < D) {
            s.window = std::max(s.window, in_columns(end > first + 2 ? end - 2 : first, end));
            out += in_columns(end > first + 2 ? end - 2 : first, end);
            arrivals_right = in_columns(end, g1);
        }
        const std::size_t arrivals = arrivals_left + arrivals_right;
        s.outbox = device::sizing::box_capacity(out);
        s.inbox = device::sizing::box_capacity(arrivals + buffer_in(g0, g1));
        // Each exchange (exchange.cpp plan(), send(), receive_and_merge()) holds what the store had
        // and the arrivals, keeping the sorted particles: the first (SlabDriver::start) the owned
        // particles, the next ones the ghosts too, dropped at the merge. On slabs of 4 columns or
        // more it sorts only the edges where the reorder scratch holds them (or always, where the
        // edges go through arrays of their own: `edges_apart`), deciding so on the capacity before
        // the store grows: each edge alone, and only on a side with arrivals (the left: the
        // arrivals and the kept particles of the first two columns; the right: those of the last
        // two, the dropped and the arrivals).
        const std::size_t owned = in_columns(first, end);
        const std::size_t x = s.columns >= 4 && arrivals_left > 0 ? in_columns(first, first + 2) : 0;
        const std::size_t y = s.columns >= 4 && arrivals_right > 0 ? in_columns(end - 2, end) : 0;
        // The first exchange grows the store before the cell tables are made (and on the edge path,
        // in send(), before the inbox is); the sort before it (exchange.cpp sort_uploaded()) sorted
        // the owned particles.
        auto exchange = [&](std::size_t held, std::size_t dropped, bool first_one) {
            const std::size_t kept = held - dropped;
            const std::size_t m_left = arrivals_left > 0 ? arrivals_left + x : 0;
            const std::size_t m_right = arrivals_right > 0 ? y + dropped + arrivals_right : 0;
            const std::size_t m = m_left + m_right;
            const bool edges = s.columns >= 4 && arrivals > 0 && kept > 0 && x + y < kept &&
                               (edges_apart || m * device::sizing::kParticleBytes <= s.capacity * device::sizing::kFloat4);
            at.sorted = first_one ? owned : s.active;
            at.tables = !first_one;
            at.inbox = !first_one || !edges;
            grow(held + arrivals, true);
            if (edges) s.edge = std::max(s.edge, std::max(m_left, m_right));
        };
        exchange(owned, 0, true);
        exchange(owned + arrivals, arrivals, false);
    }
    return shares;
}

}  // namespace clsph::detail
