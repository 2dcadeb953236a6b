#include "device/cell_pipeline.hpp"
#include "device/sizing.hpp"

#include "cl/errors.hpp"
#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>

namespace clsph::device {
using cl_rt::set_args;

CellPipeline::CellPipeline(cl_rt::Device& device, const Grid& grid, bool fused)
    : device_(device),
      grid_(grid),
      fused_(fused),
      sort_(device, RadixSort::Config{0, 0, sizing::kDigitBits, "sort", fused}),
      edge_sort_(device, RadixSort::Config{0, 0, 8, "edge_sort", fused}),
      scan_(device, Scan::Config{0, 0, "scan", fused}),
      wg_(device.work_group_size(128)) {
    const std::string opts = grid.kernel_options();
    auto k = [&](const char* name) { return device.kernel("cells.cl", name, opts); };
    keys_k_ = k("cell_keys");
    gather4_k_ = k("gather_float4");
    gather1_k_ = k("gather_uint");
    flag_k_ = k("flag_cells");
    scatter_k_ = k("scatter_cells");
    ranges_k_ = k("neighbour_ranges");
    locate_k_ = k("locate_keys");
    settle_k_ = k("settle_owned");
    flag_range_k_ = k("flag_key_range");
    gather_range_k_ = k("gather_key_range");
    edge_keys_k_ = k("edge_keys");
    edge_gather_k_ = k("edge_gather");
    edge_place_k_ = k("edge_place");
    arrival_keys_k_ = k("arrival_keys");
    drift_keys_k_ = k("drift_settle_keys");
    tables_bounded_k_ = k("tables_bounded");
    ranges_bounded_k_ = k("neighbour_ranges_bounded");
    cell_count_ = device.alloc(2 * sizeof(cl_uint), "cell count");
    device.fill(cell_count_, cl_uint{0}, 2);
    reserve_cells(0);  // grown to the first count (with the headroom) by the first tables
}

void CellPipeline::store_count() {
    if (counted_on_device_) return;  // (there already)
    const cl_uint k[2] = {cl_rt::checked_uint(cells_), cl_rt::checked_uint(cells_)};
    device_.write(cell_count_, k, 2);
}

void CellPipeline::reserve_cells(std::size_t k) {
    if (k <= cell_capacity_ && cell_key_) return;
    const std::size_t cap = sizing::cell_capacity(k, cell_headroom_);
    cell_key_ = cl_rt::Buffer();
    cell_start_ = cl_rt::Buffer();
    ranges_ = cl_rt::Buffer();
    cell_key_ = device_.alloc(cap * sizeof(cl_uint), "cell keys");
    cell_start_ = device_.alloc((cap + 1) * sizeof(cl_uint), "cell starts");
    ranges_ = device_.alloc(cap * grid_.rows() * 2 * sizeof(cl_uint), "neighbour ranges");
    cell_capacity_ = cap;
}

void CellPipeline::sort_pairs(RadixSort& sorter, cl_rt::Buffer& keys, cl_rt::Buffer& vals, std::size_t n,
                              ParticleStore& ps, unsigned bits) {
    if (bits == 0) bits = grid_.key_bits();
    // The reorder scratch is free while keys sort (the reorder comes after): the sort ping-pongs
    // through it rather than through 8 bytes a particle of its own. Only stores of a few dozen
    // particles are too small to lend it.
    if (RadixSort::borrowed_elements(n) * sizeof(cl_uint) <= ps.scratch.bytes())
        sorter.sort_through(keys, vals, n, bits, ps.scratch);
    else
        sorter.sort(keys, vals, n, bits);
}

CellPassResult CellPipeline::run(ParticleStore& ps) {
    const std::size_t n = ps.ranges.active();
    CellPassResult result;
    const auto at = sort_particles(ps, n, 0, n, {grid_.params().invalid_key});
    const std::size_t n_valid = at[0];
    // Particles outside the domain sort last: dropping them is shrinking the owned range.
    result.removed = n - n_valid;
    ps.ranges = ParticleRanges{0, n_valid, 0};
    result.cells = build_tables(ps, n_valid);
    result.active = n_valid;
    return result;
}

std::vector<std::size_t> CellPipeline::sort_particles(ParticleStore& ps, std::size_t n, std::size_t keep_first,
                                                      std::size_t keep_end, const std::vector<std::uint32_t>& thresholds) {
    enqueue_sort(ps, SortSelection{n, keep_first, keep_end, n, KeyRange{0, grid_.params().invalid_key}, true});
    return locate(ps, n, thresholds);
}

void CellPipeline::enqueue_sort(ParticleStore& ps, const SortSelection& s) {
    enqueue_sort_keys(ps, s);
    enqueue_reorder(ps, s.n, 0);
}

void CellPipeline::enqueue_sort_keys(ParticleStore& ps, const SortSelection& s) {
    if (s.n == 0) return;
    set_args(keys_k_, s.n, s.keep_first, s.keep_end, s.tail_first, s.keys.lo, s.keys.hi, cl_uint{s.settle ? 1u : 0u},
             grid_.params(), ps.pos, ps.keys, ps.vals);
    device_.launch("cells.keys", keys_k_, s.n, wg_);
    sort_pairs(sort_, ps.keys, ps.vals, s.n, ps);
}

bool CellPipeline::drift_histogram_usable() {
    if (drift_histogram_checked_) return drift_histogram_k_() != nullptr;
    drift_histogram_checked_ = true;
    cl::Kernel k = device_.kernel("drift_histogram.cl", "drift_keys_histogram",
                                  grid_.kernel_options() + " " + sort_.tile_options());
    // It runs in the sort's work-groups: where the device cannot (more registers than the sort's
    // kernels), the drift and keys take their own launch and the sort its histogram.
    const std::size_t limit = cl_rt::guarded("querying a kernel's work-group size", device_.label(), [&] {
        return k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device_.cl_device());
    });
    if (limit >= sort_.config().work_group || device_.quirks().kernel_work_group_size_understated)
        drift_histogram_k_ = k;
    return drift_histogram_k_() != nullptr;
}

void CellPipeline::enqueue_drift_sort_keys(ParticleStore& ps, KeyRange keep, const Drift& drift) {
    const std::size_t n = ps.ranges.active();
    ensure_counters();
    if (n == 0) return;
    const unsigned bits = grid_.key_bits();
    if (RadixSort::borrowed_elements(n) * sizeof(cl_uint) <= ps.scratch.bytes() && drift_histogram_usable()) {
        // With the sort's first histogram (kernels/drift_histogram.cl): a launch fewer.
        const std::size_t tile = sort_.tile(), groups = (n + tile - 1) / tile;
        const cl_rt::Buffer& counts = sort_.first_counts(n);
        set_args(drift_histogram_k_, n, ps.ranges.first_owned(), ps.ranges.end_owned(), keep.lo, keep.hi,
                 grid_.params(), drift.dt, drift.rho0, ps.pos, ps.velrho, ps.accel, ps.id, drift.halt, counters_,
                 ps.keys, ps.vals, cl_uint{sort_.first_bits(bits)}, groups, counts);
        const std::size_t wg = sort_.config().work_group;
        device_.launch("cells.drift_keys", drift_histogram_k_, groups * wg, wg);
        sort_.sort_through_counted(ps.keys, ps.vals, n, bits, ps.scratch);
        return;
    }
    set_args(drift_keys_k_, n, ps.ranges.first_owned(), ps.ranges.end_owned(), keep.lo, keep.hi, grid_.params(),
             drift.dt, drift.rho0, ps.pos, ps.velrho, ps.accel, ps.id, drift.halt, counters_, ps.keys, ps.vals);
    device_.launch("cells.drift_keys", drift_keys_k_, n, wg_);
    sort_pairs(sort_, ps.keys, ps.vals, n, ps);
}

void CellPipeline::enqueue_reorder(ParticleStore& ps, std::size_t n, std::size_t dst_offset) {
    if (n == 0) return;
    gather_arrays(ps, n, dst_offset, ps.vals, "reorder");
}

void CellPipeline::gather_arrays(ParticleStore& ps, std::size_t n, std::size_t dst_offset, const cl_rt::Buffer& order,
                                 const std::string& name) {
    // Reorder through the one scratch buffer: gather A into scratch, then swap A and scratch.
    for (cl_rt::Buffer* a : {&ps.pos, &ps.velrho, &ps.accel}) {
        set_args(gather4_k_, n, dst_offset, order, *a, ps.scratch);
        device_.launch(name + ".float4", gather4_k_, n, wg_);
        a->swap(ps.scratch);
    }
    // ids go through the same scratch (larger than they need) and are copied back: the two buffers
    // differ in size, so they cannot trade places.
    set_args(gather1_k_, n, dst_offset, order, ps.id, ps.scratch);
    device_.launch(name + ".uint", gather1_k_, n, wg_);
    device_.copy(ps.scratch, ps.id, n * sizeof(cl_uint), dst_offset * sizeof(cl_uint), dst_offset * sizeof(cl_uint));
}

void CellPipeline::set_order(CellOrder order) {
    order_ = order == CellOrder::morton ? CellOrder::morton : CellOrder::arrival;
    // Built here, on the thread that sets the run up, and only for morton: a run in arrival order
    // never compiles cell_order.cl.
    if (order_ == CellOrder::morton && !within_k_()) {
        const std::string opts = grid_.kernel_options();
        within_k_ = device_.kernel("cell_order.cl", "order_within_cells", opts);
        codes_k_ = device_.kernel("cell_order.cl", "sub_cell_codes", opts);
    }
}

void CellPipeline::order_within_cells(ParticleStore& ps, std::size_t n) {
    if (order_ != CellOrder::morton || n == 0) return;
    const auto scale = sub_cell_scales(grid_.params());
    set_args(codes_k_, n, scale[0], scale[1], scale[2], ps.pos, ps.scratch);
    device_.launch("cells.within_codes", codes_k_, n, wg_);
    set_args(within_k_, n, ps.keys, ps.scratch, ps.vals);
    device_.launch("cells.within", within_k_, n, wg_);
    gather_arrays(ps, n, 0, ps.vals, "cells.within");
}

void CellPipeline::enqueue_edge_sort(ParticleStore& ps, const EdgeSort& e) {
    auto& d = device_;
    const std::size_t m = std::max(e.left, e.end - e.right);
    if (m == 0) return;
    if (edge_keys_.bytes() < m * sizeof(cl_uint)) {
        const std::size_t cap = sizing::box_capacity(m);
        edge_keys_ = cl_rt::Buffer();
        edge_vals_ = cl_rt::Buffer();
        edge_keys_ = d.alloc(cap * sizeof(cl_uint), "edge sort keys");
        edge_vals_ = d.alloc(cap * sizeof(cl_uint), "edge sort values");
    }
    // Each edge goes through four arrays side by side: the reorder scratch, or, where the halo may
    // be overlapped with the interior's forces (which sit in the scratch then), arrays of its own.
    if (edges_apart_ && edge_arrays_.bytes() < edge_scratch_bytes(m)) {
        edge_arrays_ = cl_rt::Buffer();
        edge_arrays_ = d.alloc(edge_scratch_bytes(sizing::box_capacity(m)), "edge sort arrays");
    }
    if (!edges_apart_ && edge_scratch_bytes(m) > ps.scratch.bytes())
        throw Error("edge sort of " + std::to_string(m) + " particles does not fit the reorder scratch");
    const auto bound = [&](std::uint32_t k) { return std::clamp(k, e.keys.lo, e.keys.hi); };
    // Just above the last valid key below k: a column's keys do not fill its 2^shift_s codes (the
    // a and b parts stop at n_a and n_b), and no valid key lies between, so an upper bound there
    // sorts the same and may need a bit less (SPHERIC-2 at dp 0.006: two columns in 16 bits, not 17).
    const GridParams& g = grid_.params();
    const auto tight = [&](std::uint32_t k) {
        if (k == 0 || g.shift_s >= 32) return k;
        const std::uint32_t c = std::min<std::uint32_t>((k - 1) >> g.shift_s, g.n_s - 1);
        const std::uint64_t last = std::uint64_t{grid_.key(c, g.n_a - 1, g.n_b - 1)} + 1;
        return static_cast<std::uint32_t>(std::min<std::uint64_t>(k, last));
    };
    // The left edge: every key from left_top up sorts as left_top; the right edge: every key below
    // right_bottom as right_bottom. Those particles were kept, in sorted order, and come after
    // (before) every other entry of their edge, so a stable sort leaves them where the full keys
    // would: the order, within cells too, is the same.
    if (e.left > 0) sort_edge(ps, 0, e.left, e.left, e, e.keys.lo, tight(bound(e.left_top)));
    if (e.end > e.right)
        sort_edge(ps, e.right, e.end - e.right, e.valid_right, e, bound(e.right_bottom), tight(e.keys.hi));
}

void CellPipeline::sort_edge(ParticleStore& ps, std::size_t first, std::size_t count, std::size_t kept,
                             const EdgeSort& e, std::uint32_t code_lo, std::uint32_t code_hi) {
    auto& d = device_;
    code_hi = std::max(code_hi, code_lo);  // bounds that cross (a cut moved past them): one code
    // Codes 0 .. code_hi - code_lo (valid keys) and one more (dropped): the bits that hold them.
    const std::uint64_t codes = std::uint64_t{code_hi} - code_lo + 2;
    unsigned bits = 1;
    while (bits < 32 && (std::uint64_t{1} << bits) < codes) ++bits;
    if (codes > (std::uint64_t{1} << 32)) {  // no room for the dropped code: sort on the keys themselves
        code_lo = 0;
        code_hi = grid_.params().invalid_key - 1;
        bits = grid_.key_bits();
    }
    set_args(edge_keys_k_, first, count, e.drop_first, e.drop_end, e.keys.lo, e.keys.hi, code_lo, code_hi, ps.pos,
             edge_keys_, edge_vals_);
    d.launch("edge.keys", edge_keys_k_, count, wg_);
    // Edges apart: through the sort's own buffers (of the edges' size), not the reorder scratch.
    if (edges_apart_)
        edge_sort_.sort(edge_keys_, edge_vals_, count, bits);
    else
        sort_pairs(edge_sort_, edge_keys_, edge_vals_, count, ps, bits);
    // The edge's entries of all four arrays in sorted order into the edge arrays (one launch), then the
    // first `kept` back into place (one launch).
    const cl_rt::Buffer& arrays = edges_apart_ ? edge_arrays_ : ps.scratch;
    set_args(edge_gather_k_, count, edge_vals_, ps.pos, ps.velrho, ps.accel, ps.id, arrays);
    d.launch("edge.gather", edge_gather_k_, count, wg_);
    set_args(edge_place_k_, count, first, kept, arrays, ps.pos, ps.velrho, ps.accel, ps.id);
    d.launch("edge.place", edge_place_k_, kept, wg_);
}

void CellPipeline::enqueue_rekey(ParticleStore& ps, std::size_t n) {
    if (n == 0) return;
    set_args(keys_k_, n, std::size_t{0}, n, n, cl_uint{0}, grid_.params().invalid_key, cl_uint{0}, grid_.params(), ps.pos,
             ps.keys, ps.vals);
    device_.launch("cells.rekey", keys_k_, n, wg_);
}

void CellPipeline::enqueue_sort_with_arrivals(ParticleStore& ps, std::size_t held, std::size_t left, std::size_t right,
                                              std::size_t keep_first, std::size_t keep_end, KeyRange keys) {
    const std::size_t n = held + left + right;
    if (n == 0) return;
    set_args(arrival_keys_k_, held, left, right, keep_first, keep_end, keys.lo, keys.hi, grid_.params().invalid_key,
             ps.pos, ps.keys, ps.vals);
    device_.launch("cells.arrival_keys", arrival_keys_k_, n, wg_);
    sort_pairs(sort_, ps.keys, ps.vals, n, ps);
    enqueue_reorder(ps, n, 0);
}

std::vector<std::size_t> CellPipeline::locate(ParticleStore& ps, std::size_t n,
                                              const std::vector<std::uint32_t>& thresholds) {
    cl_rt::EventSet done;
    enqueue_locate(ps, n, thresholds, done);
    done.wait("locating keys in the sorted particles");
    return std::vector<std::size_t>(located_host_.begin(), located_host_.end());
}

void CellPipeline::enqueue_locate(ParticleStore& ps, std::size_t n, const std::vector<std::uint32_t>& thresholds,
                                  cl_rt::EventSet& done) {
    auto& d = device_;
    located_host_.resize(d, thresholds.size());
    std::fill(located_host_.data(), located_host_.data() + thresholds.size(), 0u);
    if (n == 0 || thresholds.empty()) return;
    const std::size_t t = thresholds.size();
    if (thresholds_.bytes() < t * sizeof(cl_uint)) {
        thresholds_ = d.alloc(t * sizeof(cl_uint), "key thresholds");
        located_ = d.alloc(t * sizeof(cl_uint), "located keys");
    }
    thresholds_host_.resize(d, t);
    std::copy(thresholds.begin(), thresholds.end(), thresholds_host_.data());
    d.write_async(thresholds_, thresholds_host_.data(), t * sizeof(cl_uint), 0, done);
    set_args(locate_k_, t, n, ps.keys, thresholds_, located_);
    d.launch("cells.locate", locate_k_, t, std::min<std::size_t>(wg_, 32));
    d.read_async(located_, located_host_.data(), t * sizeof(cl_uint), 0, done);
}

std::size_t CellPipeline::build_tables(ParticleStore& ps, std::size_t n) {
    cl_rt::EventSet done;
    enqueue_count_cells(ps, n, done);
    done.wait("counting the non-empty cells");
    return finish_tables(ps, n);
}

void CellPipeline::enqueue_count_cells(ParticleStore& ps, std::size_t n, cl_rt::EventSet& done) {
    auto& d = device_;
    cell_count_host_.resize(d, 1);
    cell_count_host_[0] = 0;
    if (n == 0) return;
    // Compaction of non-empty cells: flags, scan (n + 1 entries), scatter.
    scan_cell_starts(ps, n);
    d.read_async(ps.vals, cell_count_host_.data(), sizeof(cl_uint), n * sizeof(cl_uint), done);
}

void CellPipeline::scan_cell_starts(ParticleStore& ps, std::size_t n) {
    // Every build of the tables comes through here, right after the last sort or merge of the
    // step, whatever the path (one device, the exchange's merges, the step ahead).
    order_within_cells(ps, n);
    if (fused_) {  // the flags counted by the scan as it reads the keys: a launch fewer
        scan_.exclusive_starts(ps.keys, ps.vals, n);
        return;
    }
    set_args(flag_k_, n, ps.keys, ps.vals);
    device_.launch("cells.flag", flag_k_, n, wg_);
    scan_.exclusive(ps.vals, ps.vals, n);
}

void CellPipeline::enqueue_interior_tables(ParticleStore& ps, std::size_t n, std::size_t hole) {
    if (order_ != CellOrder::arrival)
        throw Error("the interior's cell tables need the arrival order within cells (the morton order moves particles)");
    if (!edges_apart_) throw Error("the interior's forces would sit in the reorder scratch the edge sort uses");
    interior_capacity_ = 0;
    if (n == 0) return;
    // Keys from pos.w for [hole, n) (cells.keys drops [0, hole) without reading it), then key 0 for
    // the hole, so that the keys stay sorted for the tables' binary searches: one cell of column 0
    // at the front, which no interior cell's rows reach (they stay two columns clear of the old
    // first column).
    const cl_uint invalid = grid_.params().invalid_key;
    set_args(keys_k_, n, hole, n, n, cl_uint{0}, invalid, cl_uint{0}, grid_.params(), ps.pos, ps.keys, ps.vals);
    device_.launch("cells.interior_keys", keys_k_, n, wg_);
    if (hole > 0) device_.fill(ps.keys, cl_uint{0}, hole, 0);
    // Bounded (no count comes back): a count above the capacity sets a flag no kernel reads; the
    // caller compares the merged count with interior_capacity() instead.
    if (!interior_halt_) interior_halt_ = device_.alloc(sizeof(cl_uint), "interior halt flag");
    enqueue_tables_bounded(ps, n, interior_halt_);
    interior_capacity_ = cell_capacity_;
}

std::size_t CellPipeline::finish_tables(ParticleStore& ps, std::size_t n) {
    auto& d = device_;
    cells_ = 0;
    counted_on_device_ = false;
    if (n == 0) return 0;
    const std::size_t k = cell_count_host_.empty() ? 0 : cell_count_host_[0];
    reserve_cells(k);
    set_args(scatter_k_, n, cell_capacity_, ps.keys, ps.vals, cell_key_, cell_start_);
    d.launch("cells.scatter", scatter_k_, n, wg_);  // and each particle's cell, in place
    set_args(ranges_k_, k, grid_.params(), cell_key_, cell_start_, ranges_);
    d.launch("cells.ranges", ranges_k_, k, wg_);
    cells_ = k;
    return k;
}

void CellPipeline::enqueue_tables_bounded(ParticleStore& ps, std::size_t n, const cl_rt::Buffer& halt) {
    auto& d = device_;
    if (n == 0) return;
    const std::size_t cap = cell_capacity_;
    scan_cell_starts(ps, n);
    set_args(tables_bounded_k_, n, cap, ps.keys, ps.vals, cell_key_, cell_start_, cell_count_, halt);
    d.launch("cells.scatter_bounded", tables_bounded_k_, std::max(n, cap + 1), wg_);
    set_args(ranges_bounded_k_, cap, grid_.params(), cell_count_, cell_key_, cell_start_, ranges_);
    d.launch("cells.ranges", ranges_bounded_k_, cap, wg_);
    cells_ = cap;
    counted_on_device_ = true;
}

void CellPipeline::enqueue_settle(ParticleStore& ps, KeyRange keep, cl_rt::EventSet& done, KeyRange split) {
    auto& d = device_;
    counters_host_.resize(d, sizing::kSettleCounters);
    std::fill(counters_host_.data(), counters_host_.data() + sizing::kSettleCounters, 0u);
    if (ps.ranges.owned == 0) return;  // an idle device: nothing to settle, no round trip
    ensure_counters();
    d.fill(counters_, cl_uint{0}, sizing::kSettleCounters);
    set_args(settle_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), keep.lo, keep.hi, split.lo, split.hi,
             grid_.params(), ps.pos, counters_);
    d.launch("cells.settle", settle_k_, ps.ranges.owned, wg_);
    d.read_async(counters_, counters_host_.data(), sizing::kSettleCounters * sizeof(cl_uint), 0, done);
}

void CellPipeline::ensure_counters() {
    if (counters_) return;
    counters_ = device_.alloc(sizing::kSettleCounters * sizeof(cl_uint), "exchange counters");
    device_.fill(counters_, cl_uint{0}, sizing::kSettleCounters);
}

void CellPipeline::enqueue_settle_on_device(ParticleStore& ps, KeyRange keep) {
    auto& d = device_;
    ensure_counters();
    if (ps.ranges.owned == 0) return;
    set_args(settle_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), keep.lo, keep.hi, cl_uint{0}, cl_uint{0},
             grid_.params(), ps.pos, counters_);
    d.launch("cells.settle", settle_k_, ps.ranges.owned, wg_);
}

Settled CellPipeline::settled() const {
    if (counters_host_.size() < sizing::kSettleCounters) return {};
    return {counters_host_[0], counters_host_[1], counters_host_[2], counters_host_[3], counters_host_[4]};
}

void CellPipeline::begin_gathers(std::size_t blocks) {
    gather_counts_.resize(device_, blocks);
    std::fill(gather_counts_.data(), gather_counts_.data() + blocks, 0u);
}

void CellPipeline::enqueue_gather(ParticleStore& ps, std::size_t first, std::size_t end, KeyRange keys,
                                  ParticleArrays& out, std::size_t base, std::size_t block, cl_rt::EventSet& done) {
    auto& d = device_;
    if (end <= first) return;
    if (block >= gather_counts_.size()) throw Error("enqueue_gather: block " + std::to_string(block) + " not begun");
    if (out.capacity() < base + (end - first)) throw Error("enqueue_gather: the outbox is too small for the window");
    const std::size_t n = end - first;
    if (flags_.bytes() < (n + 1) * sizeof(cl_uint)) {
        flags_ = cl_rt::Buffer();
        flags_ = d.alloc(sizing::flag_capacity(n) * sizeof(cl_uint), "exchange flags");
    }
    set_args(flag_range_k_, first, end, keys.lo, keys.hi, ps.pos, flags_);
    d.launch("exchange.flag", flag_range_k_, n, wg_);
    scan_.exclusive(flags_, flags_, n);
    set_args(gather_range_k_, first, end, keys.lo, keys.hi, base, flags_, ps.pos, ps.velrho, ps.accel, ps.id, out.pos,
             out.velrho, out.accel, out.id);
    d.launch("exchange.gather", gather_range_k_, n, wg_);
    // In-order queue: this reads the total before the next block's scan overwrites it.
    d.read_async(flags_, &gather_counts_[block], sizeof(cl_uint), n * sizeof(cl_uint), done);
}

}  // namespace clsph::device
