// mDBC on one device (kernels/mdbc.cl, mdbc_lanes.cl): the ghost-node offsets by id, and the pass
// that gives the owned boundary particles their densities (and, with no-slip walls, the fluid's
// velocity at their ghost nodes, as v_wall - v_G into the force pass's output: wall_velocity.h).
#include "device/physics.hpp"

#include "cl/kernel_args.hpp"

#include <algorithm>

namespace clsph::device {

void Physics::set_ghost_nodes(const std::vector<std::array<float, 3>>& by_id) {
    ghost_count_ = by_id.size();
    std::vector<float> raw(4 * std::max<std::size_t>(ghost_count_, 1), 0.0f);
    for (std::size_t i = 0; i < ghost_count_; ++i)
        for (int k = 0; k < 3; ++k) raw[4 * i + k] = by_id[i][k];
    ghost_ = cl_rt::Buffer();
    ghost_ = device_.alloc(raw.size() * sizeof(float), "mDBC ghost nodes");
    device_.write(ghost_, raw.data(), raw.size());
    if (motion_segments_ > 0) {  // the offsets at rest, which turn_ghost_nodes turns into ghost_
        ghost_rest_ = cl_rt::Buffer();
        ghost_rest_ = device_.alloc(raw.size() * sizeof(float), "mDBC ghost nodes at rest");
        device_.write(ghost_rest_, raw.data(), raw.size());
    }
}

void Physics::boundary_densities(ParticleStore& ps, const CellPipeline& cells) {
    boundary_densities(ps, cells, ps.scratch);
}

void Physics::boundary_densities(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& wall_seen) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0 || !mdbc_) return;
    if (!ghost_) set_ghost_nodes({});
    if (motion_segments_ > 0) turn_ghost_nodes(ps);
    cl_rt::set_args(mdbc_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), cells.cells(), cells.cell_count(),
                    cl_uint{cells.counted_on_device() ? 1u : 0u}, grid_.params(), sp_, ps.pos, cells.cell_key(),
                    cells.cell_start(), ps.velrho, ps.id, ghost_, ghost_count_, halt_);
    if (no_slip_) mdbc_k_.setArg(15, wall_seen.get());
    if (form_ == Interaction::lanes)
        device_.launch("sph.mdbc", mdbc_k_, cells.cells(), 1);  // a work-item per cell, as forces
    else
        device_.launch("sph.mdbc", mdbc_k_, n, wg_);
}

}  // namespace clsph::device
