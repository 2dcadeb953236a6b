// Floating rigid bodies on the host (clsph/scene.hpp, Floating; docs/scenes.md): per body its
// state in double — centre, velocity, orientation (unit quaternion w, x, y, z), angular velocity,
// and the accelerations from the last force — integrated in the steps of the engine's two
// integrators (kernels/integrate.cl), and the pose its particles are put at (a row of the motion
// table, kernels/motion.cl type 4: x = C + R r0, v = V + W x R r0). The fluid's force and the
// moment sums come from the devices (kernels/floating.cl) in 64-bit fixed point, summed here.
//   Leap-frog:  drift: C += (V + A dt/2) dt, q = exp((W + Al dt/2) dt) q, placed with V + A dt,
//               W + Al dt (the velocities the force pass sees, as the fluid's predicted ones);
//               kick:  V += (A + A') dt/2, W += (Al + Al') dt/2, A = A', Al = Al'.
//   Symplectic: predict: C_h = C + V dt/2, q_h = exp(W dt/2) q, V_h = V + A dt/2, W_h = W + Al dt/2;
//               correct (A_h, Al_h at the half step): V += A_h dt, W += Al_h dt, C = C_h + V dt/2,
//               q = exp(W dt/2) q_h; then A, Al from the forces at the new pose.
// A = F / M + g; Al = I^-1 (T - W x I W) with I = R I0 R^T; components on axes the scene holds
// fixed (Floating::free_translation, free_rotation) are 0.
#pragma once
#include "clsph/scene.hpp"
#include "scene/floating.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::multi {

// Fixed point of the device sums: 2^-32 N (kernels/floating.cl).
constexpr double kBodyFixedScale = 4294967296.0;
constexpr std::size_t kBodySums = 12;  // F (3), then M_ab = sum r0_a F_b (9, row-major)

struct BodyState {
    // The state at the last whole step: centre (m), velocity (m/s), angular velocity (rad/s),
    // orientation from rest (w, x, y, z); the accelerations the integrator holds (of the last
    // whole step) and the newest ones (of the last forces).
    std::array<double, 3> x{}, v{}, w{};
    std::array<double, 4> q{1, 0, 0, 0};
    std::array<double, 3> a{}, alpha{}, a_new{}, alpha_new{};
    std::array<double, 3> force{}, torque{};  // the fluid's last force (N) and torque about the centre (N m)
    // Where the particles were last put: centre, orientation, velocity, angular velocity.
    std::array<double, 3> x_p{}, v_p{}, w_p{};
    std::array<double, 4> q_p{1, 0, 0, 0};
    static constexpr std::size_t kDoubles = 44;
    void save(std::vector<double>& out) const;
    static BodyState load(const double* in);
};

class RigidBodies {
public:
    explicit RigidBodies(const Scene& scene);
    std::size_t size() const { return bodies_.size(); }
    const std::vector<scene::FloatingBody>& bodies() const { return bodies_; }
    const std::vector<BodyState>& states() const { return state_; }
    void set_states(const std::vector<BodyState>& s) { state_ = s; }

    // The fluid's sums at the pose the particles were put at (kBodySums a body, fixed point, summed
    // over every device and rank): force, torque and the newest accelerations.
    void set_forces(const std::vector<std::int64_t>& sums);
    void drift(double dt);    // Leap-frog's drift (the start and kick(0): the accelerations taken)
    void kick(double dt);     // after set_forces at the drifted pose
    void predict(double dt);  // Symplectic
    void correct(double dt);  // after set_forces at the half step

    // Per body the motion table's pose (kernels/motion.cl type 7): R (9, row-major), T = C - C0 (3),
    // V (3), W (3).
    std::vector<std::array<double, 18>> poses() const;
    static std::array<double, 9> rotation(const std::array<double, 4>& q);

private:
    std::vector<scene::FloatingBody> bodies_;
    std::vector<BodyState> state_;
    Vec3 g_{0, 0, 0};
};

}  // namespace clsph::multi
