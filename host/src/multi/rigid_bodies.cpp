#include "multi/rigid_bodies.hpp"

#include <cmath>

namespace clsph::multi {
namespace {

using V3 = std::array<double, 3>;
using Q = std::array<double, 4>;
using M3 = std::array<double, 9>;

V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
V3 mul(const M3& m, const V3& v) {
    return {m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2], m[6] * v[0] + m[7] * v[1] + m[8] * v[2]};
}
M3 mul(const M3& a, const M3& b) {
    M3 o{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) o[3 * i + j] += a[3 * i + k] * b[3 * k + j];
    return o;
}
M3 transpose(const M3& a) { return {a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]}; }
V3 solve(const M3& m, const V3& b) {  // Cramer's rule (I is symmetric positive definite)
    const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
    const M3 inv{(m[4] * m[8] - m[5] * m[7]) / det, (m[2] * m[7] - m[1] * m[8]) / det, (m[1] * m[5] - m[2] * m[4]) / det,
                 (m[5] * m[6] - m[3] * m[8]) / det, (m[0] * m[8] - m[2] * m[6]) / det, (m[2] * m[3] - m[0] * m[5]) / det,
                 (m[3] * m[7] - m[4] * m[6]) / det, (m[1] * m[6] - m[0] * m[7]) / det, (m[0] * m[4] - m[1] * m[3]) / det};
    return mul(inv, b);
}
Q qmul(const Q& a, const Q& b) {
    return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
// q turned by the rotation vector phi (world frame): exp(phi / 2) q, normalised.
Q turn(const Q& q, const V3& phi) {
    const double th = std::sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]);
    Q d{1, 0, 0, 0};
    if (th > 0) {
        const double s = std::sin(0.5 * th) / th;
        d = {std::cos(0.5 * th), phi[0] * s, phi[1] * s, phi[2] * s};
    }
    Q o = qmul(d, q);
    const double n = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3]);
    for (auto& c : o) c /= n;
    return o;
}
V3 axpy(const V3& y, const V3& x, double a) { return {y[0] + a * x[0], y[1] + a * x[1], y[2] + a * x[2]}; }

}  // namespace

void BodyState::save(std::vector<double>& out) const {
    for (const auto* e : {&x, &v, &w, &a, &alpha, &a_new, &alpha_new, &force, &torque, &x_p, &v_p, &w_p})
        out.insert(out.end(), e->begin(), e->end());
    out.insert(out.end(), q.begin(), q.end());
    out.insert(out.end(), q_p.begin(), q_p.end());
}

BodyState BodyState::load(const double* in) {
    BodyState s;
    for (auto* e : {&s.x, &s.v, &s.w, &s.a, &s.alpha, &s.a_new, &s.alpha_new, &s.force, &s.torque, &s.x_p, &s.v_p, &s.w_p})
        for (auto& c : *e) c = *in++;
    for (auto& c : s.q) c = *in++;
    for (auto& c : s.q_p) c = *in++;
    return s;
}

RigidBodies::RigidBodies(const Scene& scene) : bodies_(scene::floating_bodies(scene)), g_(scene.physics.gravity) {
    for (const auto& b : bodies_) {
        BodyState s;
        s.x = s.x_p = b.centre;
        s.v = s.v_p = b.velocity;  // the scene's initial velocities (zero unless given)
        s.w = s.w_p = b.angular_velocity;
        state_.push_back(s);
    }
}

M3 RigidBodies::rotation(const Q& q) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

void RigidBodies::set_forces(const std::vector<std::int64_t>& sums) {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
        BodyState& s = state_[b];
        const std::int64_t* f = sums.data() + b * kBodySums;
        for (int k = 0; k < 3; ++k) s.force[k] = static_cast<double>(f[k]) / kBodyFixedScale;
        M3 M{};
        for (int k = 0; k < 9; ++k) M[k] = static_cast<double>(f[3 + k]) / kBodyFixedScale;
        // T = sum (R r0) x F: with N = R M (N_jk = sum (R r0)_j F_k), T_i = eps_ijk N_jk.
        const M3 R = rotation(s.q_p);
        const M3 N = mul(R, M);
        s.torque = {N[5] - N[7], N[6] - N[2], N[1] - N[3]};
        for (int k = 0; k < 3; ++k) s.a_new[k] = s.force[k] / bodies_[b].mass + g_[k];
        const M3 I = mul(mul(R, bodies_[b].inertia), transpose(R));
        const V3 gyro = cross(s.w_p, mul(I, s.w_p));
        s.alpha_new = solve(I, {s.torque[0] - gyro[0], s.torque[1] - gyro[1], s.torque[2] - gyro[2]});
        for (int k = 0; k < 3; ++k) {  // the axes the scene holds fixed
            if (!bodies_[b].free_translation[k]) s.a_new[k] = 0;
            if (!bodies_[b].free_rotation[k]) s.alpha_new[k] = 0;
        }
    }
}

void RigidBodies::drift(double dt) {
    for (auto& s : state_) {
        s.x = s.x_p = axpy(s.x, axpy(s.v, s.a, 0.5 * dt), dt);
        const V3 turn_by = axpy(s.w, s.alpha, 0.5 * dt);
        s.q = s.q_p = turn(s.q, {turn_by[0] * dt, turn_by[1] * dt, turn_by[2] * dt});
        s.v_p = axpy(s.v, s.a, dt);
        s.w_p = axpy(s.w, s.alpha, dt);
    }
}

void RigidBodies::kick(double dt) {
    for (auto& s : state_) {
        for (int k = 0; k < 3; ++k) {
            s.v[k] += (s.a[k] + s.a_new[k]) * (0.5 * dt);
            s.w[k] += (s.alpha[k] + s.alpha_new[k]) * (0.5 * dt);
        }
        s.a = s.a_new;
        s.alpha = s.alpha_new;
    }
}

void RigidBodies::predict(double dt) {
    for (auto& s : state_) {
        s.x_p = axpy(s.x, s.v, 0.5 * dt);
        s.q_p = turn(s.q, {s.w[0] * 0.5 * dt, s.w[1] * 0.5 * dt, s.w[2] * 0.5 * dt});
        s.v_p = axpy(s.v, s.a, 0.5 * dt);
        s.w_p = axpy(s.w, s.alpha, 0.5 * dt);
    }
}

void RigidBodies::correct(double dt) {
    for (auto& s : state_) {
        s.v = axpy(s.v, s.a_new, dt);
        s.w = axpy(s.w, s.alpha_new, dt);
        s.x = s.x_p = axpy(s.x_p, s.v, 0.5 * dt);
        s.q = s.q_p = turn(s.q_p, {s.w[0] * 0.5 * dt, s.w[1] * 0.5 * dt, s.w[2] * 0.5 * dt});
        s.v_p = s.v;
        s.w_p = s.w;
    }
}

std::vector<std::array<double, 18>> RigidBodies::poses() const {
    std::vector<std::array<double, 18>> out;
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
        const BodyState& s = state_[b];
        std::array<double, 18> p{};
        const M3 R = rotation(s.q_p);
        for (int k = 0; k < 9; ++k) p[k] = R[k];
        for (int k = 0; k < 3; ++k) {
            p[9 + k] = s.x_p[k] - bodies_[b].centre[k];
            p[12 + k] = s.v_p[k];
            p[15 + k] = s.w_p[k];
        }
        out.push_back(p);
    }
    return out;
}

}  // namespace clsph::multi
