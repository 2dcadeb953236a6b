#include "device/cell_pipeline.hpp"

#include "cl/errors.hpp"

namespace clsph::device {

CellPipeline::CellPipeline(cl_rt::Device& device, const Grid& grid)
    : device_(device), grid_(grid), sort_(device), scan_(device), wg_(device.work_group_size(128)) {
    const std::string opts = grid.kernel_options();
    keys_k_ = device.kernel("cells.cl", "cell_keys", opts);
    gather4_k_ = device.kernel("cells.cl", "gather_float4", opts);
    gather1_k_ = device.kernel("cells.cl", "gather_uint", opts);
    flag_k_ = device.kernel("cells.cl", "flag_cells", opts);
    scatter_k_ = device.kernel("cells.cl", "scatter_cells", opts);
    cell_of_k_ = device.kernel("cells.cl", "cell_of_particle", opts);
    ranges_k_ = device.kernel("cells.cl", "neighbour_ranges", opts);
    summary_ = device.alloc(2 * sizeof(cl_uint), "cell summary");
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
    ranges_ = device_.alloc(cap * 9 * 2 * sizeof(cl_uint), "neighbour ranges");
    cell_capacity_ = cap;
}

CellPassResult CellPipeline::run(ParticleStore& ps) {
    auto& d = device_;
    const cl_uint n = static_cast<cl_uint>(ps.ranges.active());
    const GridParams g = grid_.params();
    CellPassResult result;
    if (n == 0) {
        cells_ = 0;
        return result;
    }

    keys_k_.setArg(0, n);
    keys_k_.setArg(1, g);
    keys_k_.setArg(2, ps.pos.get());
    keys_k_.setArg(3, ps.keys.get());
    keys_k_.setArg(4, ps.vals.get());
    d.launch("cells.keys", keys_k_, n, wg_);

    sort_.sort(ps.keys, ps.vals, n, grid_.key_bits());

    // Reorder through the one scratch buffer: gather A into scratch, then swap A and scratch.
    for (cl_rt::Buffer* a : {&ps.pos, &ps.velrho, &ps.accel}) {
        gather4_k_.setArg(0, n);
        gather4_k_.setArg(1, ps.vals.get());
        gather4_k_.setArg(2, a->get());
        gather4_k_.setArg(3, ps.scratch.get());
        d.launch("reorder.float4", gather4_k_, n, wg_);
        a->swap(ps.scratch);
    }
    // ids go through the same scratch (larger than they need) and are copied back: the two buffers
    // differ in size, so they cannot trade places.
    gather1_k_.setArg(0, n);
    gather1_k_.setArg(1, ps.vals.get());
    gather1_k_.setArg(2, ps.id.get());
    gather1_k_.setArg(3, ps.scratch.get());
    d.launch("reorder.uint", gather1_k_, n, wg_);
    d.copy(ps.scratch, ps.id, n * sizeof(cl_uint));

    // Compaction of non-empty cells: flags, scan (in place, n + 1 entries), scatter.
    const cl_uint none_outside = n;
    d.fill(summary_, none_outside, 2);
    flag_k_.setArg(0, n);
    flag_k_.setArg(1, g.invalid_key);
    flag_k_.setArg(2, ps.keys.get());
    flag_k_.setArg(3, ps.vals.get());
    flag_k_.setArg(4, summary_.get());
    d.launch("cells.flag", flag_k_, n, wg_);
    scan_.exclusive(ps.vals, ps.vals, n);
    d.copy(ps.vals, summary_, sizeof(cl_uint), n * sizeof(cl_uint), 0);
    cl_uint summary[2];
    d.read(summary_, summary, 2);
    const std::size_t k_all = summary[0];
    const std::size_t n_valid = summary[1];
    const std::size_t k_valid = k_all - (n_valid < n ? 1 : 0);

    reserve_cells(k_all);
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

    ranges_k_.setArg(0, static_cast<cl_uint>(k_valid));
    ranges_k_.setArg(1, g);
    ranges_k_.setArg(2, cell_key_.get());
    ranges_k_.setArg(3, cell_start_.get());
    ranges_k_.setArg(4, ranges_.get());
    d.launch("cells.ranges", ranges_k_, k_valid, wg_);

    // Particles outside the domain sort last: dropping them is shrinking the owned range.
    result.removed = n - n_valid;
    ps.ranges.owned -= std::min(ps.ranges.owned, result.removed);
    cells_ = k_valid;
    result.cells = k_valid;
    result.active = ps.ranges.active();
    return result;
}

}  // namespace clsph::device
