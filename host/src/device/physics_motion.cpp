// The solids that move (clsph/scene.hpp Motion): the motion table on the device, the boundary
// particles set from their closed form after each drift, and mDBC's ghost nodes turned with them
// (kernels/motion.cl).
#include "device/physics.hpp"

#include "cl/errors.hpp"
#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

namespace clsph::device {

void Physics::set_motion(const MotionTable& table) {
    if (table.empty()) return;
    // Without cl_khr_fp64 (no clock either: synchronous steps) the kernel runs in float.
    motion_float_ = !has_clock_;
    const std::string motion_opts = grid_.kernel_options() + (motion_float_ ? " -DCLSPH_MOTION_FLOAT" : "");
    motion_k_ = device_.kernel("motion.cl", "move_solids", motion_opts);
    if (mdbc_) turn_k_ = device_.kernel("motion.cl", "turn_ghost_nodes", motion_opts);
    motion_segments_ = table.segment_count();
    motion_ids_ = table.ids();
    auto upload = [&](const std::vector<double>& v, const char* what) {
        if (!motion_float_) {
            cl_rt::Buffer b = device_.alloc(v.size() * sizeof(double), what);
            device_.write(b, v.data(), v.size());
            return b;
        }
        const std::vector<float> f(v.begin(), v.end());
        cl_rt::Buffer b = device_.alloc(f.size() * sizeof(float), what);
        device_.write(b, f.data(), f.size());
        return b;
    };
    motion_table_ = upload(table.segments, "motion segments");
    const std::vector<float> rest = table.rest.empty() ? std::vector<float>(4, 0.0f) : table.rest;
    motion_rest_ = device_.alloc(rest.size() * sizeof(float), "motion rest positions");
    device_.write(motion_rest_, rest.data(), rest.size());
    motion_local_ = upload(table.local.empty() ? std::vector<double>{0, 0, 0, -1} : table.local, "motion local positions");
}

void Physics::set_motion_time_args(cl::Kernel& k, cl_uint i) const {
    const cl_rt::Buffer& clock = motion_time_.on_clock ? clock_ : motion_table_;  // unread off the clock
    // The times are doubles, or floats on a device without them (set_args takes no double: the
    // kernels' floats are guarded there).
    auto real = [&](cl_uint at, double v) {
        if (motion_float_)
            k.setArg(at, static_cast<float>(v));
        else
            k.setArg(at, v);
    };
    k.setArg(i++, clock.get());
    k.setArg(i++, cl_uint{motion_time_.on_clock ? 1u : 0u});
    real(i++, motion_time_.time);
    real(i++, motion_time_.dt);
    real(i++, motion_time_.fraction);
    k.setArg(i++, cl_rt::checked_uint(motion_segments_));
    k.setArg(i++, motion_table_.get());
}

void Physics::launch_motion(ParticleStore& ps, bool on_clock, double time, double dt, double fraction) {
    const std::size_t n = ps.ranges.owned;
    if (motion_segments_ == 0) return;
    motion_time_ = {on_clock, time, dt, fraction};
    if (n == 0) return;
    cl_uint i = 0;
    motion_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.first_owned()));
    motion_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.end_owned()));
    motion_k_.setArg(i++, grid_.params());
    set_motion_time_args(motion_k_, i);
    i += 7;
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{&motion_rest_, &motion_local_}) motion_k_.setArg(i++, b->get());
    motion_k_.setArg(i++, cl_rt::checked_uint(motion_ids_));
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{&ps.pos, &ps.velrho, &ps.id, &halt_})
        motion_k_.setArg(i++, b->get());
    device_.launch("sph.move_solids", motion_k_, n, wg_);
}

void Physics::turn_ghost_nodes(ParticleStore& ps) {
    if (!ghost_rest_) return;  // set_ghost_nodes was given none
    const std::size_t n = ps.ranges.owned;
    cl_uint i = 0;
    turn_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.first_owned()));
    turn_k_.setArg(i++, cl_rt::checked_uint(ps.ranges.end_owned()));
    set_motion_time_args(turn_k_, i);
    i += 7;
    turn_k_.setArg(i++, motion_local_.get());
    turn_k_.setArg(i++, cl_rt::checked_uint(std::min(motion_ids_, ghost_count_)));
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{&ghost_rest_, &ghost_, &ps.id, &halt_})
        turn_k_.setArg(i++, b->get());
    device_.launch("sph.turn_ghost_nodes", turn_k_, n, wg_);
}

void Physics::move_solids(ParticleStore& ps, double time, double dt, double fraction) {
    launch_motion(ps, false, time, dt, fraction);
}

void Physics::move_solids_on_clock(ParticleStore& ps) { launch_motion(ps, true, 0.0, 0.0, 1.0); }

}  // namespace clsph::device
