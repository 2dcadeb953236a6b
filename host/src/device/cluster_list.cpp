#include "device/cluster_list.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"
#include "device/sizing.hpp"

#include <cstdint>

namespace clsph::device {

ClusterList::ClusterList(cl_rt::Device& device, const Grid& grid, float reach2)
    : device_(device), grid_(grid), reach2_(reach2), wg_(device.work_group_size(128)) {
    const std::string opts = grid.kernel_options() + kernel_options();
    boxes_k_ = device.kernel("clusters.cl", "cluster_boxes", opts);
    masks_k_ = device.kernel("clusters.cl", "cluster_masks", opts);
}

std::string ClusterList::kernel_options() const {
    return " -DCLSPH_CLUSTERS=" + std::to_string(sizing::kClusterSize) +
           " -DCLSPH_MASK_BITS=" + std::to_string(sizing::cluster_mask_bits(grid_.reach()));
}

void ClusterList::reserve(std::size_t indices, std::size_t scratch_bytes) {
    const bool own_boxes = !sizing::cluster_boxes_borrowed(indices, scratch_bytes);
    if (indices <= capacity_ && begin_ && own_boxes == static_cast<bool>(boxes_)) return;
    // The kernels index masks by uint: index * rows stays below 2^32.
    if (indices * grid_.rows() >= (std::uint64_t{1} << 32))
        throw Error("the clusters interaction form indexes at most 2^32 cluster rows; this device would need " +
                    std::to_string(indices * grid_.rows()) + " (use --interaction fine)");
    begin_ = cl_rt::Buffer();
    boxes_ = cl_rt::Buffer();
    masks_ = cl_rt::Buffer();
    begin_ = device_.alloc(sizing::cluster_begin_bytes(indices), "cluster starts");
    if (own_boxes) boxes_ = device_.alloc(sizing::cluster_box_bytes(indices), "cluster boxes");
    masks_ = device_.alloc(sizing::cluster_mask_bytes(indices, grid_.rows(), grid_.reach()), "cluster-pair masks");
    capacity_ = indices;
}

void ClusterList::build(ParticleStore& ps, const CellPipeline& cells, std::size_t first, std::size_t last) {
    reserve(sizing::cluster_indices(ps.capacity(), cells.cell_capacity()), ps.scratch.bytes());
    const std::size_t k = cells.cells();
    if (k == 0 || last <= first) return;
    // The boxes are needed only here: in the reorder scratch, which is free until the pass writes
    // its results (or the summation densities) there, where they fit.
    const cl_rt::Buffer& boxes = boxes_ ? boxes_ : ps.scratch;
    cl_rt::set_args(boxes_k_, k, capacity_, cells.cell_start(), ps.pos, begin_, boxes);
    device_.launch("sph.clusters.boxes", boxes_k_, k, wg_);
    cl_rt::set_args(masks_k_, first, last, grid_.params(), reach2_, ps.pos,
                    ps.vals, cells.ranges(), cells.cell_key(), cells.cell_start(), boxes, masks_);
    device_.launch("sph.clusters.list", masks_k_, last - first, wg_);
    ++builds_;
}

}  // namespace clsph::device
