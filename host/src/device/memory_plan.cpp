// The memory model (clsph/memory_plan.hpp): each buffer below is sized as the allocation it stands
// for sizes it; the file and function of that allocation are named beside it. Pure C++: the grid
// and the probes' points are host math, the device's parameters come from its DeviceInfo.
#include "clsph/memory_plan.hpp"
#include "device/memory_census.hpp"

#include "balance/balancer.hpp"
#include "clsph/error.hpp"
#include "device/grid.hpp"
#include "probes/gauges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>
#include <iterator>
#include <map>
#include <utility>

namespace clsph {
namespace {

constexpr std::size_t u32 = 4, f4 = 16;
constexpr std::size_t particle_bytes = 3 * f4 + u32;  // device::ParticleArrays::kBytesPerParticle
constexpr std::size_t step_record_doubles = 17;        // device::StepRecord::kDoubles

std::size_t ceil_div(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

// Tiles of the sort and the scan on this device (primitives_radix_sort.cpp, primitives_scan.cpp):
// 256 work-items where the device allows, 16 items each where local memory holds the tile.
struct Tiles {
    std::size_t sort = 4096, scan = 4096;
};

Tiles tiles_of(const DeviceInfo& d) {
    std::size_t wg = 1;
    while (wg * 2 <= std::min<std::size_t>(256, d.max_work_group_size ? d.max_work_group_size : 256)) wg *= 2;
    const std::size_t local = d.local_memory > 2048 ? d.local_memory - 1024 : d.local_memory;  // quirks.cpp
    auto sort_local = [&](std::size_t items) {
        const std::size_t tile = wg * items;
        return u32 * (2 * (tile + tile / 32) + 256 + 2 * wg);
    };
    auto scan_local = [&](std::size_t items) {
        const std::size_t tile = wg * items;
        return u32 * (2 * wg + (items > 4 ? tile + tile / 32 : 0));
    };
    Tiles t;
    std::size_t items = 4;
    for (std::size_t i : {16, 8})
        if (sort_local(i) <= local || local == 0) { items = i; break; }
    t.sort = wg * items;
    items = 4;
    for (std::size_t i : {16, 8})
        if (scan_local(i) <= local || local == 0) { items = i; break; }
    t.scan = wg * items;
    return t;
}

// One Scan object's tile sums: a buffer per recursion level, each as large as its largest use.
struct ScanSums {
    std::vector<std::size_t> level;
    void use(std::size_t n, std::size_t tile) {
        for (std::size_t k = 0;; ++k) {
            const std::size_t groups = ceil_div(n, tile);
            if (groups <= 1) return;
            if (level.size() <= k) level.resize(k + 1, 0);
            level[k] = std::max(level[k], (groups + 1) * u32);
            n = groups;
        }
    }
    std::size_t bytes() const {
        std::size_t b = 0;
        for (auto x : level) b += x;
        return b;
    }
};

// One RadixSort object: the digit counts and its scan's tile sums, and ping-pong keys and values
// as large as the caller's unless it borrows the reorder scratch (`lent` bytes) for them
// (cell_pipeline.cpp sort_pairs(), RadixSort::borrowed_elements()).
struct SortTemporaries {
    std::size_t alt = 0, counts = 0;
    ScanSums sums;
    void use(std::size_t caller_bytes, std::size_t n, const Tiles& t, std::size_t lent) {
        if (n < 2) return;
        const std::size_t borrowed = 2 * ((n + 63) / 64 * 64) * u32;
        if (borrowed > lent) alt = std::max({alt, caller_bytes, n * u32});
        const std::size_t table = 256 * ceil_div(n, t.sort);
        counts = std::max(counts, (table + 1) * u32);
        sums.use(table, t.scan);
    }
};

// What one device holds, in particles, at the start (several devices: an estimate of the split).
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

// The store's arrays in the order particle_store.cpp reserve() grows them when it keeps particles
// (ParticleArrays::grow, then keys and values; the scratch is freed, then made): bytes per particle,
// and 1 for the arrays of capacity + 1.
struct StoreArray {
    const char* name;
    std::size_t elem, extra;
};
constexpr StoreArray store_arrays[] = {
    {"particles: positions", f4, 0},      {"particles: velocity+density", f4, 0},
    {"particles: acceleration+drho/dt", f4, 0}, {"particles: ids", u32, 0},
    {"sort keys", u32, 1},                {"sort values / cell index", u32, 1},
};

}  // namespace

std::size_t DeviceMemoryPlan::total_bytes() const {
    std::size_t b = 0;
    for (const auto& x : buffers) b += x.bytes;
    return b;
}

std::size_t DeviceMemoryPlan::scaling_bytes() const {
    std::size_t b = 0;
    for (const auto& x : buffers) b += x.scales ? x.bytes : 0;
    return b;
}

const PlannedBuffer& DeviceMemoryPlan::largest() const {
    static const PlannedBuffer none;
    if (buffers.empty()) return none;
    return *std::max_element(buffers.begin(), buffers.end(),
                             [](const PlannedBuffer& a, const PlannedBuffer& b) { return a.bytes < b.bytes; });
}

bool DeviceMemoryPlan::fits() const {
    return (device.global_memory == 0 || total_bytes() <= device.global_memory) &&
           (device.max_allocation == 0 || largest().bytes <= device.max_allocation);
}

namespace {
// The entries [first, end) of the device that entry d is a slab of.
std::pair<std::size_t, std::size_t> slabs_of(const MemoryPlan& plan, std::size_t d) {
    const std::size_t first = d - plan.devices.at(d).slab;
    return {first, std::min(plan.devices.size(), first + plan.devices[d].slabs)};
}
}  // namespace

std::size_t MemoryPlan::device_bytes(std::size_t d) const {
    const auto [first, end] = slabs_of(*this, d);
    std::size_t b = 0;
    for (std::size_t k = first; k < end; ++k) b += devices[k].total_bytes();
    return b;
}

std::vector<std::size_t> MemoryPlan::slabs_per_device() const {
    std::vector<std::size_t> out;
    for (const auto& x : devices)
        if (x.slab == 0) out.push_back(x.slabs);
    return out;
}

std::size_t MemoryPlan::largest_particles(std::size_t d) const {
    // The device's slabs together: their scaling bytes grow with the scene, their fixed ones do not.
    // A buffer that would outgrow one allocation means one more slab (a few fixed bytes), not a limit.
    const auto [first, end] = slabs_of(*this, d);
    std::size_t scaling = 0, fixed = 0;
    for (std::size_t k = first; k < end; ++k) {
        scaling += devices[k].scaling_bytes();
        fixed += devices[k].fixed_bytes();
    }
    const double per = scaling ? static_cast<double>(scaling) / static_cast<double>(particles) : 0.0;
    const double room = static_cast<double>(devices[d].device.global_memory) - static_cast<double>(fixed);
    if (per <= 0 || room <= 0) return 0;
    return static_cast<std::size_t>(room / per);
}

std::size_t MemoryPlan::largest_particles() const {
    std::size_t n = devices.empty() ? 0 : SIZE_MAX;
    for (std::size_t d = 0; d < devices.size(); ++d) n = std::min(n, largest_particles(d));
    return n;
}

double MemoryPlan::dp_for(std::size_t n) const {
    if (n == 0 || particles == 0) return 0;
    return dp * std::cbrt(static_cast<double>(particles) / static_cast<double>(n));
}

bool MemoryPlan::fits() const {
    for (std::size_t d = 0; d < devices.size(); ++d) {
        const auto& x = devices[d];
        if (!x.fits()) return false;
        if (x.slab == 0 && x.device.global_memory && device_bytes(d) > x.device.global_memory) return false;
    }
    return true;
}

namespace {

device::Grid grid_of(const Scene& scene) {
    return device::Grid(device::Box{scene.domain.min, scene.domain.max}, scene.physics.support(), scene.domain.split_axis,
                        scene.domain.periodic, device::reach_for(scene.physics.support(), scene.physics.dp));
}

}  // namespace

namespace detail {

MemoryCensus census_of(const Scene& scene, const Particles& p) {
    const device::Grid grid = grid_of(scene);
    const std::uint32_t invalid = grid.params().invalid_key;
    MemoryCensus c;
    c.particles = p.size();
    c.per_column.assign(grid.params().n_s, 0);
    c.boundary_per_column.assign(grid.params().n_s, 0);
    c.cells_per_column.assign(grid.params().n_s, 0);
    std::vector<std::uint32_t> key(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        std::array<float, 3> off{};
        key[i] = grid.locate(p.position[i], off);
        if (key[i] != invalid) {
            const std::size_t col = grid.cell_of_key(key[i])[0];
            ++c.per_column[col];
            c.boundary_per_column[col] += p.type[i] != ParticleType::fluid;  // partition.cpp census()
        }
        if (p.type[i] == ParticleType::boundary) {
            c.any_boundary = true;
            c.max_boundary_id = std::max<std::uint32_t>(c.max_boundary_id, p.id[i]);
        }
    }
    key.erase(std::remove(key.begin(), key.end(), invalid), key.end());
    std::sort(key.begin(), key.end());
    key.erase(std::unique(key.begin(), key.end()), key.end());
    for (auto k : key) ++c.cells_per_column[grid.cell_of_key(k)[0]];
    return c;
}

MemoryCensus census_of(const Scene& scene, const scene::LatticePlan& plan) {
    // Per column, each piece's cells: the cells of its coordinates on the other two axes (a
    // boundary plane that is not a layer: its layer rows by every column and every row by its
    // layer columns). Removed fluid points are ignored (an upper bound by a few boundary cells).
    const device::Grid grid = grid_of(scene);
    const std::size_t columns = grid.params().n_s;
    MemoryCensus c;
    c.particles = static_cast<std::size_t>(plan.count());
    c.per_column.assign(columns, 0);
    c.boundary_per_column.assign(columns, 0);
    c.cells_per_column.assign(columns, 0);
    c.any_boundary = plan.boundary_count > 0;
    c.max_boundary_id = plan.boundary_count > 0 ? static_cast<std::uint32_t>(plan.boundary_count - 1) : 0;
    auto key_pos = [&](int axis) {
        for (int k = 0; k < 3; ++k)
            if (grid.axis(k) == axis) return k;
        return 0;
    };
    struct Parts {
        std::vector<std::uint32_t> all, layer;  // distinct key parts of the coordinates, of the layer ones
    };
    std::vector<std::array<Parts, 2>> parts(plan.pieces.size());
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> planes(plan.pieces.size());  // (plane, column)
    for (std::size_t k = 0; k < plan.pieces.size(); ++k) {
        const auto& piece = plan.pieces[k];
        for (int p = 1; p < 3; ++p) {
            const int kp = key_pos(piece.axis[p].axis);
            auto& out = parts[k][p - 1];
            for (std::size_t i = 0; i < piece.axis[p].size(); ++i) {
                std::uint32_t cell = 0;
                float off = 0.0f;
                if (!grid.locate_axis(kp, piece.axis[p].x[i], cell, off)) continue;
                out.all.push_back(grid.key_part(kp, cell));
                if (piece.fluid || piece.axis[p].layer[i]) out.layer.push_back(grid.key_part(kp, cell));
            }
            for (auto* v : {&out.all, &out.layer}) v->erase(std::unique(v->begin(), v->end()), v->end());
        }
        for (std::size_t i = 0; i < piece.axis[0].size(); ++i) {
            std::uint32_t col = 0;
            float off = 0.0f;
            if (!grid.locate_axis(0, piece.axis[0].x[i], col, off)) continue;
            c.per_column[col] += static_cast<std::size_t>(piece.plane_count[i]);
            if (!piece.fluid) c.boundary_per_column[col] += static_cast<std::size_t>(piece.plane_count[i]);
            planes[k].push_back({i, col});
        }
    }
    std::vector<std::vector<std::size_t>> in_column(columns);  // (piece, plane) pairs by column
    std::vector<std::uint32_t> keys;
    for (std::size_t col = 0; col < columns; ++col) {
        keys.clear();
        for (std::size_t k = 0; k < plan.pieces.size(); ++k) {
            const auto& piece = plan.pieces[k];
            bool full = false, partial = false;
            for (const auto& [plane, pc] : planes[k])
                if (pc == col && piece.plane_count[plane] > 0)
                    (piece.fluid || piece.axis[0].layer[plane] ? full : partial) = true;
            const auto& a = parts[k][0];
            const auto& b = parts[k][1];
            auto add = [&](const std::vector<std::uint32_t>& x, const std::vector<std::uint32_t>& y) {
                for (auto u : x)
                    for (auto v : y) keys.push_back(u | v);
            };
            if (full) add(a.all, b.all);
            if (partial && !full) {
                add(a.layer, b.all);
                add(a.all, b.layer);
            }
        }
        std::sort(keys.begin(), keys.end());
        c.cells_per_column[col] = static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
    }
    return c;
}

}  // namespace detail

MemoryPlan plan_memory(const Scene& scene, const Particles& p, const std::vector<DeviceInfo>& devices,
                       const Options& options) {
    return detail::plan_memory(scene, detail::census_of(scene, p), devices, options);
}

MemoryPlan plan_memory(const Scene& scene, const std::vector<DeviceInfo>& devices, const Options& options) {
    if (options.setup_on_device && scene::LatticePlan::supports(scene))
        return detail::plan_memory(scene, detail::census_of(scene, scene::LatticePlan::make(scene)), devices, options);
    return plan_memory(scene, scene.build_particles(), devices, options);
}

namespace detail {

namespace {
MemoryPlan plan_slabs(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                      const Options& options);
constexpr std::size_t most_slabs = 64;  // per device
}  // namespace

MemoryPlan plan_memory(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                       const Options& options) {
    // One slab per device, then one more at a time on the devices where a slab's largest buffer
    // exceeds the largest allocation (the cuts move with the slab count, so plan again). Slabs
    // hold their neighbours' halo columns too, so on a narrow domain more slabs stop helping: a
    // device whose worst slab has not shrunk in three tries keeps its count (and does not fit).
    std::vector<std::size_t> slabs(devices.size(), 1), stalled(devices.size(), 0);
    std::vector<double> best(devices.size(), 0.0);
    for (;;) {
        std::vector<DeviceInfo> expanded;
        for (std::size_t i = 0; i < devices.size(); ++i) expanded.insert(expanded.end(), slabs[i], devices[i]);
        MemoryPlan plan = plan_slabs(scene, census, expanded, options);
        bool more = false;
        std::size_t at = 0;
        for (std::size_t i = 0; i < devices.size(); ++i) {
            double worst = 0;  // the largest buffer of the device's slabs over one allocation
            for (std::size_t k = 0; k < slabs[i]; ++k) {
                auto& x = plan.devices.at(at + k);
                x.slab = k;
                x.slabs = slabs[i];
                if (devices[i].max_allocation)
                    worst = std::max(worst, static_cast<double>(x.largest().bytes) / static_cast<double>(devices[i].max_allocation));
            }
            at += slabs[i];
            if (worst <= 1.0) continue;
            if (slabs[i] == 1 || worst < best[i]) {
                best[i] = worst;
                stalled[i] = 0;
            } else {
                ++stalled[i];
            }
            if (stalled[i] < 3 && slabs[i] < most_slabs) {
                ++slabs[i];
                more = true;
            }
        }
        if (more) continue;
        for (std::size_t i = 0; i < devices.size(); ++i)
            if (slabs[i] > 1)
                plan.notes.push_back("device #" + std::to_string(devices[i].index) + " " + devices[i].name + " runs as " +
                                     std::to_string(slabs[i]) +
                                     " slabs: one slab's buffers would exceed its CL_DEVICE_MAX_MEM_ALLOC_SIZE (" +
                                     std::to_string(devices[i].max_allocation) + " bytes)");
        return plan;
    }
}

namespace {

MemoryPlan plan_slabs(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                      const Options& options) {
    MemoryPlan plan;
    plan.particles = census.particles;
    plan.dp = scene.physics.dp;
    const std::size_t D = std::max<std::size_t>(devices.size(), 1);
    const device::Grid grid = grid_of(scene);
    const std::size_t columns = grid.params().n_s;
    const auto& per_column = census.per_column;
    const std::uint32_t max_boundary_id = census.max_boundary_id;
    const bool any_boundary = census.any_boundary;
    struct {
        std::size_t size() const { return n; }
        std::size_t n;
    } p{census.particles};
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

    // The split (multi/slab_driver.cpp set_up): one device holds every particle; several, the
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
    const double headroom = options.capacity_headroom;
    for (std::size_t d = 0; d < D; ++d) {
        Share& s = shares[d];
        const std::size_t first = cuts[d], end = cuts[d + 1];
        s.columns = end - first;
        // slab_driver.cpp: capacity p.size() on one device, p.size() / D (1 + headroom) on several;
        // particle_store.cpp reserve(): a store too small grows to n (1 + headroom) + 1 (at the
        // upload or the generation nothing is kept: the old arrays go first, one allocation).
        s.capacity = D == 1 ? p.size() : static_cast<std::size_t>(static_cast<double>(p.size()) / static_cast<double>(D) * (1.0 + headroom));
        s.capacity = std::max<std::size_t>(s.capacity, 1);
        if (D == 1) {
            s.owned = p.size();
            s.active = in_columns(0, columns);
            s.cells = cells_in(0, columns);
            s.outbox = s.inbox = 1024;  // exchange.cpp: the boxes exist on one device too, at their least
            continue;
        }
        // partition.cpp split(): particles outside the domain go to device 0 with the host's upload.
        s.owned = in_columns(first, end) + (d == 0 && p.size() > inside ? p.size() - inside : 0);
        Share::Growth at{};  // where a growth keeping the particles happens
        auto grow = [&](std::size_t n, bool keep) {
            if (n <= s.capacity) return;
            const std::size_t cap = static_cast<std::size_t>(static_cast<double>(n) * (1.0 + headroom)) + 1;
            if (keep) {
                at.from = s.capacity, at.to = cap, at.edge = s.edge;
                s.kept_growths.push_back(at);
            }
            s.capacity = cap;
        };
        grow(s.owned, false);  // the upload or the generation: nothing kept
        if (s.columns == 0) {  // an idle device (the balancer's idle_empty_slabs): no ghosts, no edges
            s.outbox = s.inbox = 1024;
            continue;
        }
        // Ghosts: one column either side (partition.cpp needs()).
        const std::size_t g0 = first > 0 ? first - 1 : 0, g1 = std::min(end + 1, columns);
        s.active = in_columns(g0, g1);
        s.cells = cells_in(g0, g1);
        // exchange.cpp: windows of two columns at each edge with a neighbour go out; the neighbours'
        // edge columns come in (the ghosts).
        std::size_t total = 0, arrivals = 0;
        if (d > 0) {
            s.window = std::max(s.window, in_columns(first, std::min(first + 2, end)));
            total += in_columns(first, std::min(first + 2, end));
            arrivals += in_columns(g0, first);
        }
        if (d + 1 < D) {
            s.window = std::max(s.window, in_columns(end > first + 2 ? end - 2 : first, end));
            total += in_columns(end > first + 2 ? end - 2 : first, end);
            arrivals += in_columns(end, g1);
        }
        s.outbox = total + total / 4 + 1024;
        s.inbox = arrivals + arrivals / 4 + 1024;
        // Each exchange (exchange.cpp plan(), send(), receive_and_merge()) holds what the store had
        // and the arrivals, keeping the sorted particles: the first (SlabDriver::start) the owned
        // particles, the next ones the ghosts too, dropped at the merge. On slabs of 4 columns or
        // more it sorts only the edges (the arrivals, the dropped and the kept particles of the
        // first and last two columns) where the reorder scratch holds them, deciding so on the
        // capacity before the store grows.
        const std::size_t owned = in_columns(first, end);
        const std::size_t xy = s.columns >= 4 ? in_columns(first, first + 2) + in_columns(end - 2, end) : 0;
        // The first exchange grows the store before the cell tables are made (and on the edge path,
        // in send(), before the inbox is); the sort before it (exchange.cpp sort_uploaded()) sorted
        // the owned particles.
        auto exchange = [&](std::size_t held, std::size_t dropped, bool first_one) {
            const std::size_t kept = held - dropped, m = arrivals + dropped + xy;
            const bool edges = s.columns >= 4 && arrivals > 0 && kept > 0 && xy < kept &&
                               m * particle_bytes <= s.capacity * f4;
            at.sorted = first_one ? owned : s.active;
            at.tables = !first_one;
            at.inbox = !first_one || !edges;
            grow(held + arrivals, true);
            if (edges) s.edge = std::max(s.edge, m);
        };
        exchange(owned, 0, true);
        exchange(owned + arrivals, arrivals, false);
    }

    const bool mdbc = scene.boundary_method == BoundaryMethod::mdbc;
    const std::size_t probe_points = scene.probes.empty() ? 0 : probes::sample_points(scene).points.size();
    // The step ahead as Simulation decides it (multi/slab_driver.hpp can_step_ahead(): one slab,
    // a device with cl_khr_fp64 for the clock, Leap-frog).
    const bool ahead = D == 1 && !options.synchronous && options.steps_ahead > 0 &&
                       scene.physics.integrator != Integrator::symplectic && !devices.empty() && devices[0].fp64;

    // Every buffer of device d with stores of `cap` particles.
    auto buffers_of = [&](std::size_t d, std::size_t cap, std::size_t edge, std::size_t sorted) {
        const Share& s = shares[d];
        DeviceMemoryPlan x;
        if (d < devices.size()) x.device = devices[d];
        x.particles = s.owned;
        x.capacity = cap;
        x.cells = s.cells;
        const Tiles t = tiles_of(x.device);
        auto add = [&](const std::string& name, std::size_t bytes, bool scales = true) {
            if (bytes) x.buffers.push_back({name, bytes, scales});
        };
        // particle_arrays.cpp allocate() through particle_store.cpp allocate().
        for (const auto& a : store_arrays) add(a.name, (cap + a.extra) * a.elem);
        add("reorder scratch", cap * f4);
        // The cell sort (primitives_radix_sort.cpp), sorting the active particles.
        SortTemporaries sort, edge_sort;
        sort.use((cap + 1) * u32, D == 1 ? p.size() : sorted, t, cap * f4);  // the first sort holds those outside too
        // The edge sort of several devices: its own sort and buffers (cell_pipeline.cpp).
        const std::size_t edge_cap = edge ? edge + edge / 4 + 1024 : 0;  // cell_pipeline.cpp enqueue_edge_sort()
        if (edge) edge_sort.use(edge_cap * u32, edge, t, cap * f4);
        add("radix sort keys (ping-pong)", sort.alt + edge_sort.alt);
        add("radix sort values (ping-pong)", sort.alt + edge_sort.alt);
        add("radix sort digit counts", sort.counts + edge_sort.counts);
        // The cell pipeline's own scan (cell flags over the active particles; exchange flags).
        ScanSums cell_scan;
        cell_scan.use(s.active, t.scan);
        if (s.window) cell_scan.use(s.window, t.scan);
        add("scan tile sums", cell_scan.bytes() + sort.sums.bytes() + edge_sort.sums.bytes());
        // cell_pipeline.cpp reserve_cells(): the non-empty cells with the cell headroom, + 16.
        const std::size_t cc = s.cells + static_cast<std::size_t>(static_cast<double>(s.cells) * options.cell_headroom) + 16;
        add("cell keys", cc * u32);
        add("cell starts", (cc + 1) * u32);
        add("neighbour ranges", cc * grid.rows() * 2 * u32);
        add("cell count", 2 * u32, false);
        // physics.cpp's constructor.
        const std::size_t kick_groups = std::max<std::size_t>(1, std::min<std::size_t>(256, x.device.compute_units * 4u));
        add("kick reductions", kick_groups * 4 * sizeof(float), false);
        add("failure flag", u32, false);
        add("time step", sizeof(float), false);
        add("halt flag", u32, false);
        if (x.device.fp64) add("step clock", 4 * sizeof(double), false);  // physics.cpp: with cl_khr_fp64 only
        // physics.cpp set_ghost_nodes(): every device holds every boundary particle's, by id.
        if (mdbc) add("mDBC ghost nodes", (any_boundary ? max_boundary_id + std::size_t{1} : 1) * f4);
        // exchange.cpp: the boxes particles leave and arrive in (1024 at least, on one device too).
        for (const char* a : {"positions", "velocity+density", "acceleration+drho/dt"}) {
            add(std::string("exchange outbox: ") + a, s.outbox * f4, D > 1);
            add(std::string("exchange inbox: ") + a, s.inbox * f4, D > 1);
        }
        add("exchange outbox: ids", s.outbox * u32, D > 1);
        add("exchange inbox: ids", s.inbox * u32, D > 1);
        if (D > 1) {
            // cell_pipeline.cpp: the flags and column thresholds.
            add("exchange flags", (s.window + s.window / 4 + 1) * u32);
            add("exchange counters", 3 * u32, false);
            add("key thresholds", (s.columns + 2) * u32, false);
            add("located keys", (s.columns + 2) * u32, false);
            if (edge) {
                add("edge sort keys", edge_cap * u32);
                add("edge sort values", edge_cap * u32);
            }
        }
        if (probe_points) {
            // The step ahead samples in the queue (physics.cpp set_probe_points); otherwise
            // sample_probes() allocates when first asked (physics.cpp probe()).
            add(ahead ? "probe points (fixed)" : "probe points", probe_points * f4, false);
            add(ahead ? "probe sums (fixed)" : "probe sums", probe_points * 2 * sizeof(float), false);
        }
        if (ahead) {
            add("step records", options.steps_ahead * step_record_doubles * sizeof(double), false);
            add("exchange counters", 3 * u32, false);
        }
        return x;
    };
    for (std::size_t d = 0; d < D; ++d) {
        const Share& s = shares[d];
        DeviceMemoryPlan x = buffers_of(d, s.capacity, s.edge, s.active);
        // A growth that keeps the particles (particle_store.cpp reserve(), from an exchange) holds
        // the old arrays beside the new ones, one array at a time: its worst moment, everything else
        // still sized for the old capacity, may be the device's peak.
        for (const auto& [from, to, edge, sorted, tables, inbox] : s.kept_growths) {
            DeviceMemoryPlan g = buffers_of(d, from, edge, sorted);
            // Not made yet then: the probes' buffers (when first sampled), the cell tables and the
            // inbox before the first exchange's.
            auto later = [&, tables = tables, inbox = inbox](const PlannedBuffer& b) {
                return b.name == "probe points" || b.name == "probe sums" ||
                       (!tables && (b.name == "cell keys" || b.name == "cell starts" || b.name == "neighbour ranges")) ||
                       (!inbox && b.name.rfind("exchange inbox: ", 0) == 0);
            };
            g.buffers.erase(std::remove_if(g.buffers.begin(), g.buffers.end(), later), g.buffers.end());
            std::size_t best = 0, best_excess = 0, excess = 0;  // the arrays grown so far: new - old
            for (std::size_t k = 0; k < std::size(store_arrays); ++k) {
                const auto& a = store_arrays[k];
                const std::size_t now = excess + (to + a.extra) * a.elem;  // new k made, old k still held
                if (now > best_excess) best_excess = now, best = k;
                excess += (to - from) * a.elem;
            }
            if (g.total_bytes() + best_excess <= x.total_bytes()) continue;
            for (std::size_t k = 0; k <= best; ++k) {
                const auto& a = store_arrays[k];
                for (auto& b : g.buffers)
                    if (b.name == a.name) b.bytes = (k < best ? 0 : b.bytes) + (to + a.extra) * a.elem;
            }
            g.capacity = s.capacity;
            x = std::move(g);
            plan.notes.push_back("device " + std::to_string(d) + ": its store grows at the first exchanges (from " +
                                 std::to_string(from) + " to " + std::to_string(to) +
                                 " particles) keeping its particles; the old arrays beside the new ones are its peak");
        }
        plan.devices.push_back(std::move(x));
    }
    if (D > 1 && options.balance == BalanceMode::dynamic) {
        plan.notes.push_back("several devices, --balance dynamic: the split here is the balancer's equal-work first "
                             "cuts (those of --balance static); the calibration (its samples never larger than a "
                             "device's store) cuts by the times it measures, which can give a device more particles "
                             "and a larger store");
    }
    if (D > 1 && mdbc) {
        plan.notes.push_back("several devices with mDBC: the engine keeps cuts away from columns whose boundary "
                             "particles' ghost nodes lie beyond the halo; the split here does not, so a cut may move "
                             "by a column or two");
    }
    plan.notes.push_back("the cell tables are sized for the non-empty cells at the start (+ cell headroom); they grow "
                         "when the fluid spreads over more cells");
    return plan;
}

}  // namespace
}  // namespace detail

void check_fits(const MemoryPlan& plan) {
    if (plan.fits()) return;
    char text[512];
    std::snprintf(text, sizeof text, "physics.dp = %g: the scene needs %zu particles (%.3g)", plan.dp, plan.particles,
                  static_cast<double>(plan.particles));
    std::string msg = text;
    const double gib = 1024.0 * 1024.0 * 1024.0;
    for (std::size_t i = 0; i < plan.devices.size(); ++i) {
        const auto& d = plan.devices[i];
        if (d.slab != 0) continue;
        std::snprintf(text, sizeof text, "; %.3g GiB on device '%s' which has %.3g GiB",
                      static_cast<double>(plan.device_bytes(i)) / gib, d.device.name.c_str(),
                      static_cast<double>(d.device.global_memory) / gib);
        msg += text;
        if (d.slabs > 1) msg += " (as " + std::to_string(d.slabs) + " slabs)";
        const auto& big = d.largest();
        if (d.device.max_allocation && big.bytes > d.device.max_allocation) {
            std::snprintf(text, sizeof text, " (its largest buffer, '%s', needs %.3g GiB but one allocation may be at most %.3g GiB)",
                          big.name.c_str(), static_cast<double>(big.bytes) / gib,
                          static_cast<double>(d.device.max_allocation) / gib);
            msg += text;
        }
    }
    const std::size_t n = plan.largest_particles();
    if (n > 0) {
        std::snprintf(text, sizeof text, ". At most about %zu particles fit these devices: physics.dp >= %.3g", n, plan.dp_for(n));
        msg += text;
    }
    throw SceneError(msg + " (clsph run --dry-run prints the memory plan)");
}

}  // namespace clsph
