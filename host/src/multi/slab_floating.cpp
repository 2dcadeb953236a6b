// Floating bodies in the slab driver's step (multi/rigid_bodies.hpp): the host integrates each body
// from the fluid's force summed over every device and rank in fixed point (the same bits on any
// device count), and puts the bodies' poses into every device's motion table before the solids
// are moved (kernels/motion.cl type 7). With mDBC on several devices, the cuts kept where every
// slab holds the fluid its body particles' ghost nodes read.
#include "multi/slab_driver.hpp"

#include "device/floating_table.hpp"
#include "device/motion_table.hpp"
#include "scene/floating.hpp"

namespace clsph::multi {

void SlabDriver::set_up_motion(const Scene& scene) {
    if (!scene.has_motion() && !scene.has_floating()) return;
    // Prescribed motion: every device holds the whole table (a solid's particles may reach any
    // slab), by boundary id, from the scene's boundary particles at rest; floating bodies add a
    // row each, whose pose the host supplies.
    const device::Grid& grid = partition_.grid();
    auto table = scene.has_motion() ? device::motion_table(scene, grid) : device::MotionTable{};
    const auto floating = device::add_floating(table, scene, grid);
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (here(d)) {
            slabs_[d].physics->set_motion(table);
            slabs_[d].physics->set_floating(floating);
        }
    if (floating.bodies > 0) bodies_ = std::make_unique<RigidBodies>(scene);
}

// A new run whose bodies start moving (Floating::velocity, angular_velocity): their particles,
// still at rest where the scene put them, take V + W x r before the first force pass, so that the
// fluid's first forces, the body's first accelerations and the first time step (which counts
// boundary speeds) see the body as it starts. A resumed run's particles are the checkpoint's.
void SlabDriver::start_bodies() {
    if (!bodies_ || options_.resumed) return;
    bool moving = false;
    for (const auto& s : bodies_->states())
        for (int k = 0; k < 3; ++k) moving = moving || s.v[k] != 0 || s.w[k] != 0;
    if (!moving) return;  // no launch: runs without initial velocities are as they were
    const auto poses = bodies_->poses();
    for_each_device([&](std::size_t d) {
        Slab& s = slabs_[d];
        s.physics->set_floating_poses(poses);
        s.physics->move_solids(*s.store, options_.start_time, 0.0, 1.0);  // the rest pose: positions unchanged
        s.device->flush();
    });
}

std::vector<std::array<double, 18>> SlabDriver::drift_bodies(double dt) {
    if (!bodies_) return {};
    if (symplectic_)
        bodies_->predict(dt);
    else
        bodies_->drift(dt);
    return bodies_->poses();
}

std::vector<std::int64_t> SlabDriver::body_sums() {
    std::vector<std::int64_t> sums(bodies_->size() * kBodySums, 0);
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (here(d)) slabs_[d].physics->add_floating_sums(sums);
    if (across_ranks()) {  // integers: the sum over ranks is exact in any order (wrapping, two's complement)
        std::vector<std::uint64_t> u(sums.begin(), sums.end());
        ranks_.ranks->sum(u);
        for (std::size_t k = 0; k < u.size(); ++k) sums[k] = static_cast<std::int64_t>(u[k]);
    }
    return sums;
}

void SlabDriver::correct_bodies(double dt, double time) {
    bodies_->set_forces(body_sums());
    bodies_->correct(dt);
    const auto poses = bodies_->poses();
    for_each_device([&](std::size_t d) {
        Slab& s = slabs_[d];
        s.physics->set_floating_poses(poses);
        s.physics->move_solids(*s.store, time, dt, 1.0);  // the prescribed ones again where they were
        s.device->flush();
    });
}

void SlabDriver::set_up_body_cuts(const Scene& scene, const Particles& at_rest, const std::vector<std::array<float, 3>>& offsets) {
    body_support_ = scene.physics.support();
    const auto owner = scene::floating_body_of(scene, at_rest);
    for (std::size_t i = 0; i < at_rest.size(); ++i) {
        if (owner[i] < 0) continue;
        const auto b = static_cast<std::size_t>(owner[i]);
        const auto& g = offsets[i];
        if (g[0] == 0.0f && g[1] == 0.0f && g[2] == 0.0f) continue;  // interpolated at itself: within its own halo
        const Vec3& c = bodies_->bodies()[b].centre;
        body_ghosts_.push_back({b, {at_rest.position[i][0] - c[0], at_rest.position[i][1] - c[1], at_rest.position[i][2] - c[2]}, g});
    }
}

// The body particles and their ghost-node offsets where the bodies' last poses put them, and the
// cuts that restrict_body_cuts allows for them (a margin of one column: a body moves far less in a
// step, Symplectic's two passes included); with `move_cuts`, the present cuts moved off any it
// forbids (not before the first cuts are set). Every rank holds the same bodies, so every rank
// computes the same cuts.
void SlabDriver::keep_cuts_off_bodies(bool move_cuts) {
    if (body_ghosts_.empty()) return;
    const auto& states = bodies_->states();
    std::vector<std::array<double, 9>> R;
    for (const auto& st : states) R.push_back(RigidBodies::rotation(st.q_p));
    Particles p;
    std::vector<std::array<float, 3>> g;
    g.reserve(body_ghosts_.size());
    for (const BodyGhost& bg : body_ghosts_) {
        const auto& r = R[bg.body];
        const auto& x = states[bg.body].x_p;
        Vec3 at{}, turned{};
        for (int k = 0; k < 3; ++k) {
            const auto row = static_cast<std::size_t>(3 * k);
            at[k] = x[k] + r[row] * bg.r0[0] + r[row + 1] * bg.r0[1] + r[row + 2] * bg.r0[2];
            turned[k] = r[row] * bg.ghost[0] + r[row + 1] * bg.ghost[1] + r[row + 2] * bg.ghost[2];
        }
        p.push_back(0, ParticleType::boundary, at, {0, 0, 0}, 0.0f, 0.0f);
        g.push_back({static_cast<float>(turned[0]), static_cast<float>(turned[1]), static_cast<float>(turned[2])});
    }
    partition_.restrict_body_cuts(p, g, body_support_, 1);
    if (move_cuts) partition_.set_cuts(slabs_, Partition::cuts(slabs_));
}

void SlabDriver::take_body_forces(double dt) {
    if (!bodies_) return;
    bodies_->set_forces(body_sums());
    bodies_->kick(dt);
}

}  // namespace clsph::multi
