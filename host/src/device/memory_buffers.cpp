// The memory plan's buffers (device/memory_model.hpp): every buffer of each slab under the name the
// engine's memory tracker gives it, sized by device/sizing.hpp as the allocation sizes it, and a
// store growth's moment where the old arrays sit beside the new ones.
#include "device/memory_model.hpp"
#include "scene/open_boundaries.hpp"
#include "device/inlet_zones.hpp"
#include "device/motion_table.hpp"
#include "device/outlet_zones.hpp"

#include "clsph/testing.hpp"
#include "device/sizing.hpp"
#include "probes/gauges.hpp"
#include "scene/floating.hpp"
#include "scene/motion.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string>
#include <utility>

namespace clsph::detail {
namespace {

namespace sz = device::sizing;
constexpr std::size_t u32 = sz::kUint, f4 = sz::kFloat4;

std::size_t ceil_div(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

// Tiles of the sort and the scan on this device (primitives_radix_sort.cpp, primitives_scan.cpp);
// a device that does not say its local memory is taken to hold the largest tiles.
struct Tiles {
    std::size_t sort = 4096, scan = 4096;
};

Tiles tiles_of(const DeviceInfo& d) {
    const std::size_t wg = sz::work_group(d.max_work_group_size);
    const std::size_t local = d.local_memory ? sz::usable_local_memory(d.local_memory) : SIZE_MAX;
    return {wg * sz::sort_items(wg, local, sz::kDigitBits), wg * sz::scan_items(wg, local)};
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
// (cell_pipeline.cpp sort_pairs()).
struct SortTemporaries {
    std::size_t alt = 0, counts = 0;
    ScanSums sums;
    void use(std::size_t caller_bytes, std::size_t n, const Tiles& t, std::size_t lent) {
        if (n < 2) return;
        if (sz::borrowed_elements(n) * u32 > lent) alt = std::max({alt, caller_bytes, n * u32});
        const std::size_t entries = sz::sort_count_entries(n, t.sort, sz::kDigitBits);
        counts = std::max(counts, entries * u32);
        sums.use(entries - 1, t.scan);
    }
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

struct Context {
    const Scene& scene;
    const std::vector<DeviceInfo>& devices;
    const Options& options;
    std::size_t slabs, particles, rows, probe_points;
    bool mdbc, ahead, any_boundary;
    bool clusters;  // the clusters interaction form: its lists (cluster_list.cpp)
    bool sps;       // physics.viscosity laminar+sps: the stress (physics_sps.cpp), two halo columns
    int reach;
    std::uint32_t max_boundary_id;
    std::size_t motion_segments;  // of every moving solid and a row per floating body (0: none)
    std::size_t floating_bodies;
    bool edges_apart;  // edge sorts through arrays of their own (edges_apart_of)
};

// Where a slab's force pass may be split around the halo (multi/slab_driver.cpp set_up: several
// devices, no pass before the forces, no cluster lists, arrival order), its edge sorts go through
// arrays of their own (cell_pipeline.cpp enqueue_edge_sort()). The order as SlabDriver resolves
// `auto`: morton where every device runs lanes, the form `auto` gives CPUs.
bool edges_apart_of(const Scene& scene, const std::vector<DeviceInfo>& devices, const Options& options, std::size_t D) {
    if (D < 2 || (options.seams && (options.seams->whole_force_pass || options.seams->serialize_devices))) return false;
    if (scene.physics.density == DensityMode::summation || scene.physics.viscosity == Viscosity::laminar_sps) return false;
    const Interaction form = options.interaction != Interaction::automatic ? options.interaction : scene.run.interaction;
    if (form == Interaction::clusters) return false;
    CellOrder order = options.cell_order != CellOrder::automatic ? options.cell_order : scene.run.cell_order;
    if (order == CellOrder::automatic) {
        bool all_lanes = !devices.empty();
        for (const auto& d : devices)
            all_lanes = all_lanes && (form == Interaction::lanes || (form == Interaction::automatic && d.is_cpu()));
        order = all_lanes ? CellOrder::morton : CellOrder::arrival;
    }
    return order == CellOrder::arrival;
}

// Every buffer of slab d with stores of `cap` particles, an edge sort of `edge` and a cell sort of
// `sorted`.
DeviceMemoryPlan buffers_of(const Context& c, const Share& s, std::size_t d, std::size_t cap, std::size_t edge,
                            std::size_t sorted) {
    const std::size_t D = c.slabs;
    DeviceMemoryPlan x;
    if (d < c.devices.size()) x.device = c.devices[d];
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
    // The cell sort (primitives_radix_sort.cpp), sorting the active particles; the first sort on one
    // slab holds those outside the domain too.
    SortTemporaries sort, edge_sort;
    sort.use((cap + 1) * u32, D == 1 ? c.particles : sorted, t, cap * f4);
    // The edge sort of several slabs: its own sort and buffers (cell_pipeline.cpp enqueue_edge_sort()),
    // its ping-pong in the reorder scratch unless the edges go apart (the interior's forces sit there).
    const std::size_t edge_cap = edge ? sz::box_capacity(edge) : 0;
    if (edge) edge_sort.use(edge_cap * u32, edge, t, c.edges_apart ? 0 : cap * f4);
    add("radix sort keys (ping-pong)", sort.alt + edge_sort.alt);
    add("radix sort values (ping-pong)", sort.alt + edge_sort.alt);
    add("radix sort digit counts", sort.counts + edge_sort.counts);
    // The cell pipeline's own scan (cell flags over the active particles; exchange flags).
    ScanSums cell_scan;
    cell_scan.use(s.active, t.scan);
    if (s.window) cell_scan.use(s.window, t.scan);
    add("scan tile sums", cell_scan.bytes() + sort.sums.bytes() + edge_sort.sums.bytes());
    // cell_pipeline.cpp reserve_cells().
    const std::size_t cc = sz::cell_capacity(s.cells, c.options.cell_headroom);
    add("cell keys", cc * u32);
    add("cell starts", (cc + 1) * u32);
    add("neighbour ranges", cc * c.rows * 2 * u32);
    add("cell count", 2 * u32, false);
    if (c.clusters) {  // cluster_list.cpp reserve(): for the store's and the tables' capacity
        const std::size_t ids = sz::cluster_indices(cap, cc);
        add("cluster starts", sz::cluster_begin_bytes(ids));
        if (!sz::cluster_boxes_borrowed(ids, cap * f4)) add("cluster boxes", sz::cluster_box_bytes(ids));
        add("cluster-pair masks", sz::cluster_mask_bytes(ids, c.rows, c.reach));
    }
    if (c.sps) add("SPS stress", cap * 2 * f4);  // physics_sps.cpp sps_stress(): for the store's capacity
    // physics.cpp's constructor.
    add("kick reductions", sz::kick_groups(x.device.compute_units) * sz::kKickFloats * sizeof(float), false);
    add("failure flag", u32, false);
    add("time step", sizeof(float), false);
    add("halt flag", u32, false);
    if (x.device.fp64) add("step clock", sz::kClockDoubles * sizeof(double), false);
    // physics.cpp set_ghost_nodes(): every slab holds every boundary particle's, by id.
    if (c.mdbc) add("mDBC ghost nodes", (c.any_boundary ? c.max_boundary_id + std::size_t{1} : 1) * f4);
    // With moving solids also the offsets at rest, which turn_ghost_nodes turns.
    if (c.mdbc && c.motion_segments)
        add("mDBC ghost nodes at rest", (c.any_boundary ? c.max_boundary_id + std::size_t{1} : 1) * f4);
    // physics.cpp set_motion(): every slab holds the whole table, and per boundary id the rest
    // position and the position from the solid's reference (double where the device has fp64).
    if (c.motion_segments) {
        const std::size_t real = x.device.fp64 ? sizeof(double) : sizeof(float);
        const std::size_t ids = c.any_boundary ? c.max_boundary_id + std::size_t{1} : 1;
        add("motion segments", c.motion_segments * device::MotionTable::kSegmentDoubles * real, false);
        add("motion rest positions", ids * f4);
        add("motion local positions", ids * 4 * real);
    }
    // physics_floating.cpp set_floating() and enqueue_floating().
    if (c.floating_bodies) {
        add("floating body offsets", (c.any_boundary ? c.max_boundary_id + std::size_t{1} : 1) * f4);
        add("floating body sums", c.floating_bodies * sz::kick_groups(x.device.compute_units) * 12 * sizeof(std::int64_t), false);
        add("floating body forces", cap * f4);
    }
    // exchange.cpp: the boxes particles leave and arrive in.
    for (const char* a : {"positions", "velocity+density", "acceleration+drho/dt"}) {
        add(std::string("exchange outbox: ") + a, s.outbox * f4, D > 1);
        add(std::string("exchange inbox: ") + a, s.inbox * f4, D > 1);
    }
    add("exchange outbox: ids", s.outbox * u32, D > 1);
    add("exchange inbox: ids", s.inbox * u32, D > 1);
    // cell_pipeline.cpp: the settle's counters (every step, ahead or not); the keys the sorted
    // particles are located at (one slab: the end of the valid ones; several: each column's).
    add("exchange counters", sz::kSettleCounters * u32, false);
    add("key thresholds", (D > 1 ? s.columns + 2 : 1) * u32, false);
    add("located keys", (D > 1 ? s.columns + 2 : 1) * u32, false);
    if (D > 1) {
        // cell_pipeline.cpp: the exchange flags.
        add("exchange flags", sz::flag_capacity(s.window) * u32);
        if (edge) {
            add("edge sort keys", edge_cap * u32);
            add("edge sort values", edge_cap * u32);
            if (c.edges_apart) add("edge sort arrays", edge_cap * sz::kParticleBytes);
        }
        if (c.edges_apart) {  // the interior's bounded tables (cell_pipeline.cpp enqueue_interior_tables())
            add("interior halt flag", u32, false);
        }
    }
    if (c.probe_points) {
        // The step ahead samples in the queue (physics.cpp set_probe_points); otherwise
        // sample_probes() allocates when first asked (physics.cpp probe()).
        // Simulation::sample_probes() asked outside the ring samples as without it (both, then).
        add("probe points", c.probe_points * f4, false);
        add("probe sums", c.probe_points * 2 * sizeof(float), false);
        if (c.ahead) {
            add("probe points (fixed)", c.probe_points * f4, false);
            add("probe sums (fixed)", c.probe_points * 2 * sizeof(float), false);
        }
    }
    // device/inlet_zones.cpp: each inlet's box, direction, speed and profile; device/outlet_zones.cpp.
    for (const auto& [name, bytes] : device::InletZones::buffers(c.scene)) add(name, bytes, false);
    if (scene::has_outlet_zones(c.scene)) add("outlet zones", device::OutletZones::bytes(c.scene), false);
    if (c.ahead) {
        add("step records", c.options.steps_ahead * sz::kStepRecordDoubles * sizeof(double), false);
        // physics.cpp set_slabs(): each device's part of the reductions, per device and step in flight.
        if (c.slabs > 1) add("step sums of every device", c.options.steps_ahead * c.slabs * 4 * sizeof(float), false);
    }
    return x;
}

// A growth that keeps the particles (particle_store.cpp reserve(), from an exchange) holds the old
// arrays beside the new ones, one array at a time: its worst moment, everything else still sized
// for the old capacity, may be the slab's peak. Replaces `x` with that moment where it is larger.
void peak_of_growths(const Context& c, const Share& s, std::size_t d, DeviceMemoryPlan& x, MemoryPlan& plan) {
    for (const auto& [from, to, edge, sorted, tables, inbox] : s.kept_growths) {
        DeviceMemoryPlan g = buffers_of(c, s, d, from, edge, sorted);
        // Not made yet then: the probes' buffers (when first sampled), the cell tables and the
        // inbox before the first exchange's.
        auto later = [&, tables = tables, inbox = inbox](const PlannedBuffer& b) {
            return b.name == "probe points" || b.name == "probe sums" ||
                   (!tables && (b.name == "cell keys" || b.name == "cell starts" || b.name == "neighbour ranges" ||
                                 b.name.rfind("cluster", 0) == 0)) ||
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
}

}  // namespace

MemoryPlan plan_slabs(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                      const Options& options) {
    MemoryPlan plan;
    plan.particles = census.particles;
    plan.dp = scene.physics.dp;
    const std::size_t D = std::max<std::size_t>(devices.size(), 1);
    const bool apart = edges_apart_of(scene, devices, options, D);
    const std::vector<Share> shares = split_shares(scene, census, D, options, apart);
    // The step ahead as Simulation decides it (multi/slab_driver.hpp can_step_ahead()).
    const bool ahead = !devices.empty() && scene.inlets.empty() && !scene::has_outlet_zones(scene) &&  // synchronous steps
                       std::all_of(devices.begin(), devices.end(), [](const DeviceInfo& d) { return d.fp64; }) &&
                       sz::step_ahead(options.synchronous, options.steps_ahead, D, true,
                                      scene.physics.integrator == Integrator::symplectic, scene.run.list_buffer > 0);
    const Context c{scene,
                    devices,
                    options,
                    D,
                    census.particles,
                    grid_of(scene).rows(),
                    scene.probes.empty() ? 0 : probes::sample_points(scene).points.size(),
                    scene.boundary_method == BoundaryMethod::mdbc,
                    ahead,
                    census.any_boundary,
                    (options.interaction != Interaction::automatic ? options.interaction : scene.run.interaction) ==
                        Interaction::clusters,
                    scene.physics.viscosity == Viscosity::laminar_sps,
                    grid_of(scene).reach(),
                    census.max_boundary_id,
                    [&] {
                        std::size_t n = 0;
                        for (const auto& m : scene::moving_solids(scene)) n += m.motion.segments.size();
                        return n + scene::floating_bodies(scene).size();
                    }(),
                    scene::floating_bodies(scene).size(),
                    apart};
    for (std::size_t d = 0; d < D; ++d) {
        const Share& s = shares[d];
        DeviceMemoryPlan x = buffers_of(c, s, d, s.capacity, s.edge, s.active);
        peak_of_growths(c, s, d, x, plan);
        plan.devices.push_back(std::move(x));
    }
    if (D > 1 && options.balance == BalanceMode::dynamic) {
        plan.notes.push_back("several devices, --balance dynamic: the split here is the balancer's equal-work first "
                             "cuts (those of --balance static); the calibration (its samples never larger than a "
                             "device's store) cuts by the times it measures, which can give a device more particles "
                             "and a larger store");
    }
    if (D > 1 && c.mdbc) {
        plan.notes.push_back("several devices with mDBC: the engine keeps cuts away from columns whose boundary "
                             "particles' ghost nodes lie beyond the halo; the split here does not, so a cut may move "
                             "by a column or two");
    }
    if (D > 1 && (c.sps || c.scene.physics.density == DensityMode::summation)) {
        plan.notes.push_back(std::string("several devices with ") +
                             (c.sps ? "laminar+sps" : "summation density") +
                             ": the exchange sends two halo columns, not the one the split here counts, so each store "
                             "holds a column more of ghosts either side");
    }
    plan.notes.push_back("the cell tables are sized for the non-empty cells at the start (+ cell headroom); they grow "
                         "when the fluid spreads over more cells");
    plan.planned = scene::planned_with_inlets(scene, census.particles);
    if (!scene.inlets.empty())
        plan.notes.push_back("inlets: the stores are planned for " + std::to_string(plan.planned) + " particles (the scene's " +
                             std::to_string(census.particles) +
                             ", the inlets' buffers, and as many layers as fill the domain once along each inlet's axis); "
                             "a run that holds more grows its stores");
    return plan;
}

}  // namespace clsph::detail
