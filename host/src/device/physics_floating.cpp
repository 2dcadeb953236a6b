// Floating bodies on one device (kernels/floating.cl; host/src/multi/rigid_bodies.hpp): the fluid's
// force on the owned particles of each body and their fixed-point partial sums.
#include "device/physics.hpp"

#include "cl/errors.hpp"
#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <cstring>

namespace clsph::device {

void Physics::set_floating(const FloatingTable& table) {
    if (table.bodies == 0) return;
    floating_bodies_ = table.bodies;
    floating_row_ = table.first_row;
    floating_ids_ = table.ids();
    // The fine scheme always (it skips every particle but the bodies'); the sums in work-groups of wg_.
    const std::string opts = point_options_ + viscosity_options_ + wall_options_ + " -DWG=" + std::to_string(wg_);
    floating_k_ = device_.kernel("floating.cl", "floating_forces", opts);
    floating_sums_k_ = device_.kernel("floating.cl", "floating_sums", opts);
    floating_rest_ = device_.alloc(table.body_rest.size() * sizeof(float), "floating body offsets");
    device_.write(floating_rest_, table.body_rest.data(), table.body_rest.size());
    floating_groups_ = kick_groups_;
    floating_partials_ = device_.alloc(floating_bodies_ * floating_groups_ * 12 * sizeof(cl_long), "floating body sums");
}

void Physics::set_floating_poses(const std::vector<std::array<double, 18>>& poses) {
    if (floating_bodies_ == 0) return;
    for (std::size_t b = 0; b < poses.size(); ++b) {
        const std::size_t at = (floating_row_ + b) * MotionTable::kSegmentDoubles + 4;  // R, T, V, W
        if (motion_float_) {
            float f[18];
            for (int k = 0; k < 18; ++k) f[k] = static_cast<float>(poses[b][static_cast<std::size_t>(k)]);
            device_.write(motion_table_, f, 18, at);
        } else {
            device_.write(motion_table_, poses[b].data(), 18, at);
        }
    }
}

void Physics::enqueue_floating(ParticleStore& ps, const CellPipeline& cells) {
    if (floating_bodies_ == 0) return;
    floating_summed_ = true;
    const std::size_t n = ps.ranges.owned;
    if (n == 0) {
        device_.fill(floating_partials_, cl_long{0}, floating_bodies_ * floating_groups_ * 12);
        return;
    }
    if (floating_capacity_ < ps.capacity()) {
        floating_force_ = cl_rt::Buffer();
        floating_capacity_ = ps.capacity();
        floating_force_ = device_.alloc(floating_capacity_ * 4 * sizeof(float), "floating body forces");
    }
    const auto g = grid_.params();
    cl_uint i = 0;
    floating_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.first_owned()));
    floating_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.end_owned()));
    floating_k_.setArg(i++, g);
    floating_k_.setArg(i++, sp_.support2);
    floating_k_.setArg(i++, ps.pos.get());
    floating_k_.setArg(i++, ps.vals.get());  // each particle's cell (the fine scheme)
    floating_k_.setArg(i++, cells.ranges().get());
    floating_k_.setArg(i++, sp_);
    floating_k_.setArg(i++, ps.velrho.get());
    floating_k_.setArg(i++, ps.id.get());
    floating_k_.setArg(i++, floating_rest_.get());
    floating_k_.setArg(i++, cl_rt::checked_uint(floating_ids_));
    floating_k_.setArg(i++, floating_force_.get());
    if (no_slip_) floating_k_.setArg(i++, ps.accel.get());  // what the fluid saw (wall_velocity.h)
    device_.launch("sph.floating_forces", floating_k_, n, wg_);
    cl_rt::set_args(floating_sums_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), floating_groups_, floating_force_,
                    ps.id, floating_rest_, floating_ids_, floating_partials_);
    device_.launch("sph.floating_sums", floating_sums_k_, floating_bodies_ * floating_groups_ * wg_, wg_);
}

void Physics::add_floating_sums(std::vector<std::int64_t>& sums) {
    if (floating_bodies_ == 0) return;
    sums.resize(floating_bodies_ * 12, 0);
    if (!floating_summed_) return;  // no force pass since the last read: this device holds none of the bodies
    floating_summed_ = false;
    std::vector<cl_long> raw(floating_bodies_ * floating_groups_ * 12);
    device_.read(floating_partials_, raw.data(), raw.size());
    for (std::size_t b = 0; b < floating_bodies_; ++b)
        for (std::size_t g = 0; g < floating_groups_; ++g)
            for (std::size_t k = 0; k < 12; ++k) {
                // Unsigned: the sum wraps like the fixed point's integers (exact while it fits).
                const auto add = static_cast<std::uint64_t>(raw[(b * floating_groups_ + g) * 12 + k]);
                sums[b * 12 + k] = static_cast<std::int64_t>(static_cast<std::uint64_t>(sums[b * 12 + k]) + add);
            }
}

}  // namespace clsph::device
