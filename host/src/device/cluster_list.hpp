// The cluster-pair lists of the clusters interaction form (kernels/clusters.cl): clusters of
// sizing::kClusterSize consecutive particles of a cell, their bounding boxes, and for each cluster
// a bit mask per neighbour row of the clusters whose boxes come within the support (the boxes in
// the store's reorder scratch where they fit: sizing::cluster_boxes_borrowed). Built before the
// interaction pass on new cell tables (Physics::forces): every step, as particles are sorted
// again every step, unless run.list_buffer keeps the tables, and the lists with them, over steps
// (docs/interaction.md, "Lists kept over steps").
#pragma once
#include "cl/device.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"

namespace clsph::device {

class ClusterList {
public:
    // reach2: the square of the distance within which two clusters' boxes are listed (the
    // support, plus run.list_buffer's margin where lists are kept over steps).
    ClusterList(cl_rt::Device& device, const Grid& grid, float reach2);
    // Build options of the interaction kernels that read the lists (neighbour_loop.h).
    std::string kernel_options() const;
    // The lists of the owned particles' clusters for the tables `cells` holds now (neighbours: every
    // cluster of the tables, halo included).
    void build(ParticleStore& ps, const CellPipeline& cells) {
        build(ps, cells, ps.ranges.first_owned(), ps.ranges.end_owned());
    }
    // The lists of the clusters of particles [first, last) (summation density: every particle held).
    void build(ParticleStore& ps, const CellPipeline& cells, std::size_t first, std::size_t last);
    const cl_rt::Buffer& begins() const { return begin_; }
    const cl_rt::Buffer& masks() const { return masks_; }
    cl_rt::Buffer& begins() { return begin_; }  // (tests poison them)
    cl_rt::Buffer& masks() { return masks_; }
    std::size_t builds() const { return builds_; }
    // Cluster indices allocated (sizing::cluster_indices of the store's and the tables' capacity).
    std::size_t capacity() const { return capacity_; }

private:
    void reserve(std::size_t indices, std::size_t scratch_bytes);
    cl_rt::Device& device_;
    const Grid& grid_;
    float reach2_;
    std::size_t wg_;
    cl::Kernel boxes_k_, masks_k_;
    cl_rt::Buffer begin_, boxes_, masks_;
    std::size_t capacity_ = 0, builds_ = 0;
};

}  // namespace clsph::device
