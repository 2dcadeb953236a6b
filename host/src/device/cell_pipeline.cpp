#include "device/cell_pipeline.hpp"

#include "cl/errors.hpp"

#include <algorithm>

namespace clsph::device {
namespace {
// The four arrays of a block of `cap` particles that go between devices (the old ones freed first).
void alloc_block(cl_rt::Device& d, std::size_t cap, const std::string& what, cl_rt::Buffer& pos, cl_rt::Buffer& velrho,
                 cl_rt::Buffer& accel, cl_rt::Buffer& id) {
    const std::size_t f4 = 4 * sizeof(cl_float);
    for (cl_rt::Buffer* b : {&pos, &velrho, &accel, &id}) *b = cl_rt::Buffer();
    pos = d.alloc(cap * f4, what + ": positions");
    velrho = d.alloc(cap * f4, what + ": velocity+density");
    accel = d.alloc(cap * f4, what + ": acceleration");
    id = d.alloc(cap * sizeof(cl_uint), what + ": ids");
}
}  // namespace

CellPipeline::CellPipeline(cl_rt::Device& device, const Grid& grid)
    : device_(device),
      grid_(grid),
      sort_(device),
      edge_sort_(device, RadixSort::Config{0, 0, 8, "edge_sort"}),
      scan_(device),
      wg_(device.work_group_size(128)) {
    const std::string opts = grid.kernel_options();
    keys_k_ = device.kernel("cells.cl", "cell_keys", opts);
    gather4_k_ = device.kernel("cells.cl", "gather_float4", opts);
    gather1_k_ = device.kernel("cells.cl", "gather_uint", opts);
    flag_k_ = device.kernel("cells.cl", "flag_cells", opts);
    scatter_k_ = device.kernel("cells.cl", "scatter_cells", opts);
    cell_of_k_ = device.kernel("cells.cl", "cell_of_particle", opts);
    ranges_k_ = device.kernel("cells.cl", "neighbour_ranges", opts);
    locate_k_ = device.kernel("cells.cl", "locate_keys", opts);
    invalid_k_ = device.kernel("cells.cl", "mark_invalid", opts);
    settle_k_ = device.kernel("cells.cl", "settle_owned", opts);
    flag_range_k_ = device.kernel("cells.cl", "flag_key_range", opts);
    gather_range_k_ = device.kernel("cells.cl", "gather_key_range", opts);
    edge_keys_k_ = device.kernel("cells.cl", "edge_keys", opts);
    edge_gather_k_ = device.kernel("cells.cl", "edge_gather", opts);
    edge_place_k_ = device.kernel("cells.cl", "edge_place", opts);
    reserve_cells(1024);
}

void CellPipeline::reserve_cells(std::size_t k) {
    if (k <= cell_capacity_ && cell_key_) return;
    const std::size_t cap = k + k / 4 + 16;
    cell_key_ = cl_rt::Buffer();
    cell_start_ = cl_rt::Buffer();
    ranges_ = cl_rt::Buffer();
    cell_key_ = device_.alloc(cap * sizeof(cl_uint), "cell keys");
    cell_start_ = device_.alloc((cap + 1) * sizeof(cl_uint), "cell starts");
    ranges_ = device_.alloc(cap * grid_.rows() * 2 * sizeof(cl_uint), "neighbour ranges");
    cell_capacity_ = cap;
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

std::vector<std::size_t> CellPipeline::sort_particles(ParticleStore& ps, std::size_t n_all, std::size_t keep_first,
                                                      std::size_t keep_end, const std::vector<std::uint32_t>& thresholds) {
    enqueue_sort(ps, n_all, keep_first, keep_end);
    return locate(ps, n_all, thresholds);
}

void CellPipeline::enqueue_sort(ParticleStore& ps, std::size_t n_all, std::size_t keep_first, std::size_t keep_end) {
    enqueue_sort(ps, n_all, keep_first, keep_end, n_all, 0, grid_.params().invalid_key, true);
}

void CellPipeline::enqueue_sort(ParticleStore& ps, std::size_t n_all, std::size_t keep_first, std::size_t keep_end,
                                std::size_t tail_first, std::uint32_t key_lo, std::uint32_t key_hi, bool settle,
                                std::size_t dst_offset) {
    enqueue_sort_keys(ps, n_all, keep_first, keep_end, tail_first, key_lo, key_hi, settle);
    enqueue_reorder(ps, n_all, dst_offset);
}

void CellPipeline::enqueue_sort_keys(ParticleStore& ps, std::size_t n_all, std::size_t keep_first,
                                     std::size_t keep_end, std::size_t tail_first, std::uint32_t key_lo,
                                     std::uint32_t key_hi, bool settle) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(n_all);
    const GridParams g = grid_.params();
    if (n == 0) return;

    keys_k_.setArg(0, n);
    keys_k_.setArg(1, static_cast<cl_uint>(keep_first));
    keys_k_.setArg(2, static_cast<cl_uint>(keep_end));
    keys_k_.setArg(3, static_cast<cl_uint>(tail_first));
    keys_k_.setArg(4, static_cast<cl_uint>(key_lo));
    keys_k_.setArg(5, static_cast<cl_uint>(key_hi));
    keys_k_.setArg(6, static_cast<cl_uint>(settle ? 1 : 0));
    keys_k_.setArg(7, g);
    keys_k_.setArg(8, ps.pos.get());
    keys_k_.setArg(9, ps.keys.get());
    keys_k_.setArg(10, ps.vals.get());
    d.launch("cells.keys", keys_k_, n, wg_);

    sort_.sort(ps.keys, ps.vals, n, grid_.key_bits());
}

void CellPipeline::enqueue_reorder(ParticleStore& ps, std::size_t n_all, std::size_t dst_offset) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(n_all);
    if (n == 0) return;
    // Reorder through the one scratch buffer: gather A into scratch, then swap A and scratch.
    const cl_uint at = static_cast<cl_uint>(dst_offset);
    for (cl_rt::Buffer* a : {&ps.pos, &ps.velrho, &ps.accel}) {
        gather4_k_.setArg(0, n);
        gather4_k_.setArg(1, at);
        gather4_k_.setArg(2, ps.vals.get());
        gather4_k_.setArg(3, a->get());
        gather4_k_.setArg(4, ps.scratch.get());
        d.launch("reorder.float4", gather4_k_, n, wg_);
        a->swap(ps.scratch);
    }
    // ids go through the same scratch (larger than they need) and are copied back: the two buffers
    // differ in size, so they cannot trade places.
    gather1_k_.setArg(0, n);
    gather1_k_.setArg(1, at);
    gather1_k_.setArg(2, ps.vals.get());
    gather1_k_.setArg(3, ps.id.get());
    gather1_k_.setArg(4, ps.scratch.get());
    d.launch("reorder.uint", gather1_k_, n, wg_);
    d.copy(ps.scratch, ps.id, n * sizeof(cl_uint), dst_offset * sizeof(cl_uint), dst_offset * sizeof(cl_uint));
}

void CellPipeline::begin_inbox(std::size_t particles) {
    if (particles <= inbox_capacity_ && inbox_pos) return;
    auto& d = device_;
    inbox_capacity_ = particles + particles / 4 + 1024;
    alloc_block(d, inbox_capacity_, "exchange inbox", inbox_pos, inbox_velrho, inbox_accel, inbox_id);
}

void CellPipeline::enqueue_unpack_inbox(ParticleStore& ps, std::size_t from, std::size_t count, std::size_t to) {
    if (count == 0) return;
    const std::size_t f4 = 4 * sizeof(cl_float), u = sizeof(cl_uint);
    device_.copy(inbox_pos, ps.pos, count * f4, from * f4, to * f4);
    device_.copy(inbox_velrho, ps.velrho, count * f4, from * f4, to * f4);
    device_.copy(inbox_accel, ps.accel, count * f4, from * f4, to * f4);
    device_.copy(inbox_id, ps.id, count * u, from * u, to * u);
}

void CellPipeline::enqueue_edge_sort(ParticleStore& ps, std::size_t left, std::size_t right, std::size_t end,
                                     std::size_t drop_first, std::size_t drop_end, std::uint32_t key_lo,
                                     std::uint32_t key_hi, std::size_t valid_right) {
    auto& d = device_;
    const std::size_t m = left + (end - right);
    if (m == 0) return;
    if (edge_keys_.bytes() < m * sizeof(cl_uint)) {
        const std::size_t cap = m + m / 4 + 1024;
        edge_keys_ = cl_rt::Buffer();
        edge_vals_ = cl_rt::Buffer();
        edge_keys_ = d.alloc(cap * sizeof(cl_uint), "edge sort keys");
        edge_vals_ = d.alloc(cap * sizeof(cl_uint), "edge sort values");
    }
    edge_keys_k_.setArg(0, static_cast<cl_uint>(left));
    edge_keys_k_.setArg(1, static_cast<cl_uint>(right));
    edge_keys_k_.setArg(2, static_cast<cl_uint>(end));
    edge_keys_k_.setArg(3, static_cast<cl_uint>(drop_first));
    edge_keys_k_.setArg(4, static_cast<cl_uint>(drop_end));
    edge_keys_k_.setArg(5, static_cast<cl_uint>(key_lo));
    edge_keys_k_.setArg(6, static_cast<cl_uint>(key_hi));
    edge_keys_k_.setArg(7, grid_.params().invalid_key);
    edge_keys_k_.setArg(8, ps.pos.get());
    edge_keys_k_.setArg(9, edge_keys_.get());
    edge_keys_k_.setArg(10, edge_vals_.get());
    d.launch("edge.keys", edge_keys_k_, m, wg_);
    edge_sort_.sort(edge_keys_, edge_vals_, m, grid_.key_bits());
    // All four arrays' edge entries in sorted order into scratch (one launch), then back into place
    // (one launch): [0, left) and the right part's kept entries to [right, right + valid_right).
    if (edge_scratch_bytes(m) > ps.scratch.bytes())
        throw Error("edge sort of " + std::to_string(m) + " particles does not fit the reorder scratch");
    const cl_uint mm = static_cast<cl_uint>(m);
    edge_gather_k_.setArg(0, mm);
    edge_gather_k_.setArg(1, edge_vals_.get());
    edge_gather_k_.setArg(2, ps.pos.get());
    edge_gather_k_.setArg(3, ps.velrho.get());
    edge_gather_k_.setArg(4, ps.accel.get());
    edge_gather_k_.setArg(5, ps.id.get());
    edge_gather_k_.setArg(6, ps.scratch.get());
    d.launch("edge.gather", edge_gather_k_, m, wg_);
    edge_place_k_.setArg(0, mm);
    edge_place_k_.setArg(1, static_cast<cl_uint>(left));
    edge_place_k_.setArg(2, static_cast<cl_uint>(right));
    edge_place_k_.setArg(3, static_cast<cl_uint>(valid_right));
    edge_place_k_.setArg(4, ps.scratch.get());
    edge_place_k_.setArg(5, ps.pos.get());
    edge_place_k_.setArg(6, ps.velrho.get());
    edge_place_k_.setArg(7, ps.accel.get());
    edge_place_k_.setArg(8, ps.id.get());
    d.launch("edge.place", edge_place_k_, left + valid_right, wg_);
}

void CellPipeline::enqueue_rekey(ParticleStore& ps, std::size_t n_all) {
    const cl_uint n = static_cast<cl_uint>(n_all);
    if (n == 0) return;
    keys_k_.setArg(0, n);
    keys_k_.setArg(1, cl_uint{0});
    keys_k_.setArg(2, n);
    keys_k_.setArg(3, n);
    keys_k_.setArg(4, cl_uint{0});
    keys_k_.setArg(5, grid_.params().invalid_key);
    keys_k_.setArg(6, cl_uint{0});
    keys_k_.setArg(7, grid_.params());
    keys_k_.setArg(8, ps.pos.get());
    keys_k_.setArg(9, ps.keys.get());
    keys_k_.setArg(10, ps.vals.get());
    device_.launch("cells.rekey", keys_k_, n, wg_);
}

std::vector<std::size_t> CellPipeline::locate(ParticleStore& ps, std::size_t n_all,
                                              const std::vector<std::uint32_t>& thresholds) {
    cl_rt::EventSet done;
    enqueue_locate(ps, n_all, thresholds, done);
    done.wait("locating keys in the sorted particles");
    return std::vector<std::size_t>(located_host_.begin(), located_host_.end());
}

void CellPipeline::enqueue_locate(ParticleStore& ps, std::size_t n_all, const std::vector<std::uint32_t>& thresholds,
                                  cl_rt::EventSet& done) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(n_all);
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
    locate_k_.setArg(0, static_cast<cl_uint>(t));
    locate_k_.setArg(1, n);
    locate_k_.setArg(2, ps.keys.get());
    locate_k_.setArg(3, thresholds_.get());
    locate_k_.setArg(4, located_.get());
    d.launch("cells.locate", locate_k_, t, std::min<std::size_t>(wg_, 32));
    d.read_async(located_, located_host_.data(), t * sizeof(cl_uint), 0, done);
}

std::size_t CellPipeline::build_tables(ParticleStore& ps, std::size_t n_valid) {
    cl_rt::EventSet done;
    enqueue_count_cells(ps, n_valid, done);
    done.wait("counting the non-empty cells");
    return finish_tables(ps, n_valid);
}

void CellPipeline::enqueue_count_cells(ParticleStore& ps, std::size_t n_valid, cl_rt::EventSet& done) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(n_valid);
    cell_count_host_.resize(d, 1);
    cell_count_host_[0] = 0;
    if (n == 0) return;
    // Compaction of non-empty cells: flags, scan (in place, n + 1 entries), scatter.
    flag_k_.setArg(0, n);
    flag_k_.setArg(1, ps.keys.get());
    flag_k_.setArg(2, ps.vals.get());
    d.launch("cells.flag", flag_k_, n, wg_);
    scan_.exclusive(ps.vals, ps.vals, n);
    d.read_async(ps.vals, cell_count_host_.data(), sizeof(cl_uint), n * sizeof(cl_uint), done);
}

std::size_t CellPipeline::finish_tables(ParticleStore& ps, std::size_t n_valid) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(n_valid);
    cells_ = 0;
    if (n == 0) return 0;
    const cl_uint k = cell_count_host_.empty() ? 0 : cell_count_host_[0];
    reserve_cells(k);
    scatter_k_.setArg(0, n);
    scatter_k_.setArg(1, ps.keys.get());
    scatter_k_.setArg(2, ps.vals.get());
    scatter_k_.setArg(3, cell_key_.get());
    scatter_k_.setArg(4, cell_start_.get());
    d.launch("cells.scatter", scatter_k_, n, wg_);
    cell_of_k_.setArg(0, n);
    cell_of_k_.setArg(1, ps.keys.get());
    cell_of_k_.setArg(2, ps.vals.get());
    d.launch("cells.cell_of", cell_of_k_, n, wg_);

    ranges_k_.setArg(0, k);
    ranges_k_.setArg(1, grid_.params());
    ranges_k_.setArg(2, cell_key_.get());
    ranges_k_.setArg(3, cell_start_.get());
    ranges_k_.setArg(4, ranges_.get());
    d.launch("cells.ranges", ranges_k_, k, wg_);
    cells_ = k;
    return k;
}

void CellPipeline::enqueue_settle(ParticleStore& ps, std::uint32_t key_lo, std::uint32_t key_hi, cl_rt::EventSet& done) {
    auto& d = device_;
    counters_host_.resize(d, 3);
    std::fill(counters_host_.data(), counters_host_.data() + 3, 0u);
    if (ps.ranges.owned == 0) return;  // an idle device: nothing to settle, no round trip
    if (!counters_) counters_ = d.alloc(3 * sizeof(cl_uint), "exchange counters");
    const cl_uint zero = 0;
    d.fill(counters_, zero, 3);
    settle_k_.setArg(0, static_cast<cl_uint>(ps.ranges.first_owned()));
    settle_k_.setArg(1, static_cast<cl_uint>(ps.ranges.end_owned()));
    settle_k_.setArg(2, static_cast<cl_uint>(key_lo));
    settle_k_.setArg(3, static_cast<cl_uint>(key_hi));
    settle_k_.setArg(4, grid_.params());
    settle_k_.setArg(5, ps.pos.get());
    settle_k_.setArg(6, counters_.get());
    d.launch("cells.settle", settle_k_, ps.ranges.owned, wg_);
    d.read_async(counters_, counters_host_.data(), 3 * sizeof(cl_uint), 0, done);
}

void CellPipeline::begin_gathers(std::size_t blocks, std::size_t particles) {
    auto& d = device_;
    gather_counts_.resize(d, blocks);
    std::fill(gather_counts_.data(), gather_counts_.data() + blocks, 0u);
    if (particles > outbox_capacity_ || !outbox_pos) {
        outbox_capacity_ = particles + particles / 4 + 1024;
        alloc_block(d, outbox_capacity_, "exchange outbox", outbox_pos, outbox_velrho, outbox_accel, outbox_id);
    }
}

void CellPipeline::enqueue_gather(ParticleStore& ps, std::size_t first, std::size_t end, std::uint32_t key_lo,
                                  std::uint32_t key_hi, std::size_t base, std::size_t block, cl_rt::EventSet& done) {
    auto& d = device_;
    if (end <= first) return;
    const std::size_t n = end - first;
    if (flags_.bytes() < (n + 1) * sizeof(cl_uint)) {
        flags_ = cl_rt::Buffer();
        flags_ = d.alloc((n + n / 4 + 1) * sizeof(cl_uint), "exchange flags");
    }
    flag_range_k_.setArg(0, static_cast<cl_uint>(first));
    flag_range_k_.setArg(1, static_cast<cl_uint>(end));
    flag_range_k_.setArg(2, static_cast<cl_uint>(key_lo));
    flag_range_k_.setArg(3, static_cast<cl_uint>(key_hi));
    flag_range_k_.setArg(4, ps.pos.get());
    flag_range_k_.setArg(5, flags_.get());
    d.launch("exchange.flag", flag_range_k_, n, wg_);
    scan_.exclusive(flags_, flags_, n);
    gather_range_k_.setArg(0, static_cast<cl_uint>(first));
    gather_range_k_.setArg(1, static_cast<cl_uint>(end));
    gather_range_k_.setArg(2, static_cast<cl_uint>(key_lo));
    gather_range_k_.setArg(3, static_cast<cl_uint>(key_hi));
    gather_range_k_.setArg(4, static_cast<cl_uint>(base));
    gather_range_k_.setArg(5, flags_.get());
    gather_range_k_.setArg(6, ps.pos.get());
    gather_range_k_.setArg(7, ps.velrho.get());
    gather_range_k_.setArg(8, ps.accel.get());
    gather_range_k_.setArg(9, ps.id.get());
    gather_range_k_.setArg(10, outbox_pos.get());
    gather_range_k_.setArg(11, outbox_velrho.get());
    gather_range_k_.setArg(12, outbox_accel.get());
    gather_range_k_.setArg(13, outbox_id.get());
    d.launch("exchange.gather", gather_range_k_, n, wg_);
    // In-order queue: this reads the total before the next block's scan overwrites it.
    if (block >= gather_counts_.size()) throw Error("enqueue_gather: block " + std::to_string(block) + " not begun");
    d.read_async(flags_, &gather_counts_[block], sizeof(cl_uint), n * sizeof(cl_uint), done);
}

void CellPipeline::mark_invalid(ParticleStore& ps, std::size_t first, std::size_t end) {
    if (end <= first) return;
    invalid_k_.setArg(0, static_cast<cl_uint>(first));
    invalid_k_.setArg(1, static_cast<cl_uint>(end));
    invalid_k_.setArg(2, grid_.params().invalid_key);
    invalid_k_.setArg(3, ps.pos.get());
    device_.launch("cells.mark_invalid", invalid_k_, end - first, wg_);
}

}  // namespace clsph::device
