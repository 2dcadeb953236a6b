// Floating bodies in the slab driver's step (multi/rigid_bodies.hpp): the host integrates each body
// from the fluid's force summed over every device and rank in fixed point (the same bits on any
// device count), and puts the bodies' poses into every device's motion table before the solids
// are moved (kernels/motion.cl type 7).
#include "multi/slab_driver.hpp"

#include "device/floating_table.hpp"
#include "device/motion_table.hpp"

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

void SlabDriver::take_body_forces(double dt) {
    if (!bodies_) return;
    bodies_->set_forces(body_sums());
    bodies_->kick(dt);
}

}  // namespace clsph::multi
