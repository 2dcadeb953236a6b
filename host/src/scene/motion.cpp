#include "scene/motion.hpp"

#include "scene/lattice.hpp"
#include "scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace clsph::scene {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;

Vec3 unit(const Vec3& a) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return {a[0] / l, a[1] / l, a[2] / l};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Rotation by theta about the unit vector n (Rodrigues).
std::array<double, 9> rotation(const Vec3& n, double theta) {
    const double c = std::cos(theta), s = std::sin(theta), k = 1.0 - c;
    return {c + k * n[0] * n[0],        k * n[0] * n[1] - s * n[2], k * n[0] * n[2] + s * n[1],
            k * n[1] * n[0] + s * n[2], c + k * n[1] * n[1],        k * n[1] * n[2] - s * n[0],
            k * n[2] * n[0] - s * n[1], k * n[2] * n[1] + s * n[0], c + k * n[2] * n[2]};
}

double omega(const MotionSegment& s) { return kTwoPi / s.period; }

// The ramp-up r(tau) of a ramped segment and its rate: (1 - cos(pi tau / ramp)) / 2, then 1.
double ramp_at(const MotionSegment& s, double tau) {
    return tau < s.ramp ? 0.5 * (1.0 - std::cos(kTwoPi * 0.5 * tau / s.ramp)) : 1.0;
}
double ramp_rate(const MotionSegment& s, double tau) {
    return tau < s.ramp ? 0.5 * (kTwoPi * 0.5 / s.ramp) * std::sin(kTwoPi * 0.5 * tau / s.ramp) : 0.0;
}
// r(tau) sin(w tau) and its derivative.
double ramped_sine_at(const MotionSegment& s, double tau) { return ramp_at(s, tau) * std::sin(omega(s) * tau); }
double ramped_sine_rate(const MotionSegment& s, double tau) {
    return ramp_rate(s, tau) * std::sin(omega(s) * tau) + ramp_at(s, tau) * omega(s) * std::cos(omega(s) * tau);
}

// The rotation angle of a rotating segment after tau, and its rate.
double angle_at(const MotionSegment& s, double tau) {
    if (s.type == MotionSegment::Type::rotation || s.type == MotionSegment::Type::linear_rotation) return s.angular_velocity * tau;
    if (s.type == MotionSegment::Type::ramped_sine_rotation) return s.angle * ramped_sine_at(s, tau);
    return s.angle * (std::sin(omega(s) * tau + s.phase) - std::sin(s.phase));
}
double angle_rate(const MotionSegment& s, double tau) {
    if (s.type == MotionSegment::Type::rotation || s.type == MotionSegment::Type::linear_rotation) return s.angular_velocity;
    if (s.type == MotionSegment::Type::ramped_sine_rotation) return s.angle * ramped_sine_rate(s, tau);
    return s.angle * omega(s) * std::cos(omega(s) * tau + s.phase);
}

}  // namespace

Vec3 RigidPose::apply(const Vec3& x) const {
    return {R[0] * x[0] + R[1] * x[1] + R[2] * x[2] + T[0], R[3] * x[0] + R[4] * x[1] + R[5] * x[2] + T[1],
            R[6] * x[0] + R[7] * x[1] + R[8] * x[2] + T[2]};
}

RigidPose RigidPose::then(const RigidPose& next) const {
    RigidPose out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            out.R[3 * i + j] = next.R[3 * i] * R[j] + next.R[3 * i + 1] * R[3 + j] + next.R[3 * i + 2] * R[6 + j];
    out.T = next.apply(T);
    return out;
}

RigidPose segment_pose(const MotionSegment& s, double tau) {
    RigidPose p;
    switch (s.type) {
    case MotionSegment::Type::linear:
        for (int k = 0; k < 3; ++k) p.T[k] = s.velocity[k] * tau;
        break;
    case MotionSegment::Type::sine: {
        const double f = std::sin(omega(s) * tau + s.phase) - std::sin(s.phase);
        for (int k = 0; k < 3; ++k) p.T[k] = s.amplitude[k] * f;
        break;
    }
    case MotionSegment::Type::ramped_sine: {
        const double f = ramped_sine_at(s, tau);
        for (int k = 0; k < 3; ++k) p.T[k] = s.amplitude[k] * f;
        break;
    }
    case MotionSegment::Type::sine_rotation:
    case MotionSegment::Type::rotation:
    case MotionSegment::Type::ramped_sine_rotation: {
        p.R = rotation(unit(s.axis), angle_at(s, tau));
        const Vec3 rc = RigidPose{p.R, {0, 0, 0}}.apply(s.axis_point);
        for (int k = 0; k < 3; ++k) p.T[k] = s.axis_point[k] - rc[k];
        break;
    }
    case MotionSegment::Type::linear_rotation: {  // about the axis point, which moves with velocity
        p.R = rotation(unit(s.axis), angle_at(s, tau));
        const Vec3 rc = RigidPose{p.R, {0, 0, 0}}.apply(s.axis_point);
        for (int k = 0; k < 3; ++k) p.T[k] = s.axis_point[k] + s.velocity[k] * tau - rc[k];
        break;
    }
    }
    return p;
}

std::vector<RigidPose> segment_start_poses(const Motion& m) {
    std::vector<RigidPose> out;
    RigidPose pose;
    for (const auto& s : m.segments) {
        out.push_back(pose);
        pose = pose.then(segment_pose(s, s.end - s.start));
    }
    return out;
}

RigidPose motion_pose(const Motion& m, double t) {
    RigidPose pose;
    for (const auto& s : m.segments) {
        if (!(t > s.start)) break;
        pose = pose.then(segment_pose(s, std::min(t, s.end) - s.start));
    }
    return pose;
}

Vec3 motion_velocity(const Motion& m, double t, const Vec3& x0) {
    for (const auto& s : m.segments) {
        if (!(t >= s.start && t < s.end)) continue;
        const double tau = t - s.start;
        if (s.type == MotionSegment::Type::linear) return s.velocity;
        if (s.type == MotionSegment::Type::sine) {
            const double f = omega(s) * std::cos(omega(s) * tau + s.phase);
            return {s.amplitude[0] * f, s.amplitude[1] * f, s.amplitude[2] * f};
        }
        if (s.type == MotionSegment::Type::ramped_sine) {
            const double f = ramped_sine_rate(s, tau);
            return {s.amplitude[0] * f, s.amplitude[1] * f, s.amplitude[2] * f};
        }
        const Vec3 x = motion_pose(m, t).apply(x0);
        const Vec3 n = unit(s.axis);
        const Vec3 w{n[0] * angle_rate(s, tau), n[1] * angle_rate(s, tau), n[2] * angle_rate(s, tau)};
        if (s.type == MotionSegment::Type::linear_rotation) {
            const Vec3 c{s.axis_point[0] + s.velocity[0] * tau, s.axis_point[1] + s.velocity[1] * tau, s.axis_point[2] + s.velocity[2] * tau};
            const Vec3 r = cross(w, {x[0] - c[0], x[1] - c[1], x[2] - c[2]});
            return {s.velocity[0] + r[0], s.velocity[1] + r[1], s.velocity[2] + r[2]};
        }
        return cross(w, {x[0] - s.axis_point[0], x[1] - s.axis_point[1], x[2] - s.axis_point[2]});
    }
    return {0, 0, 0};
}

std::vector<MovingSolid> moving_solids(const Scene& scene) {
    std::vector<MovingSolid> out;
    auto centre = [](const Vec3& a, const Vec3& b) { return Vec3{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])}; };
    for (std::size_t i = 0; i < scene.walls.size(); ++i)
        if (scene.walls[i].motion.moves())
            out.push_back({scene.walls[i].motion, centre(scene.walls[i].min, scene.walls[i].max),
                           "boundaries.walls[" + std::to_string(i) + "]"});
    for (std::size_t i = 0; i < scene.solids.size(); ++i)
        if (scene.solids[i].motion.moves())
            out.push_back({scene.solids[i].motion, centre(scene.solids[i].min, scene.solids[i].max),
                           "boundaries.boxes[" + std::to_string(i) + "]"});
    for (std::size_t i = 0; i < scene.meshes.size(); ++i)
        if (scene.meshes[i].motion.moves() && !scene.meshes[i].fluid)
            out.push_back({scene.meshes[i].motion, scene.meshes[i].translate, "boundaries.meshes[" + std::to_string(i) + "]"});
    return out;
}

std::vector<std::int32_t> moving_solid_of(const Scene& scene, const Particles& p) {
    const double dp = scene.physics.dp;
    std::vector<std::pair<std::uint64_t, std::int32_t>> owner;  // lattice key, solid (first wins)
    std::int32_t next = 0;
    auto add = [&](const std::vector<Vec3>& pts) {
        for (const auto& x : pts) owner.emplace_back(lattice_key(x, dp), next);
        ++next;
    };
    for (const auto& w : scene.walls)
        if (w.motion.moves()) {
            std::vector<Vec3> pts;
            sample_walls(w, dp, pts);
            add(pts);
        }
    for (const auto& b : scene.solids)
        if (b.motion.moves()) {
            std::vector<Vec3> pts;
            sample_solid(b, dp, pts);
            add(pts);
        }
    for (const auto& m : scene.meshes)
        if (m.motion.moves() && !m.fluid) {
            std::vector<Vec3> pts, unused;
            sample_mesh(m, dp, pts, unused);
            add(pts);
        }
    std::stable_sort(owner.begin(), owner.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::int32_t> out(p.size(), -1);
    if (owner.empty()) return out;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary) continue;
        const std::uint64_t k = lattice_key(p.position[i], dp);
        const auto it = std::lower_bound(owner.begin(), owner.end(), k, [](const auto& e, std::uint64_t v) { return e.first < v; });
        if (it != owner.end() && it->first == k) out[i] = it->second;
    }
    return out;
}

std::pair<Particles, std::vector<std::array<float, 3>>> swept_ghost_nodes(const Scene& scene, const Particles& p,
                                                                          const std::vector<std::array<float, 3>>& offsets) {
    std::pair<Particles, std::vector<std::array<float, 3>>> out;
    auto& [q, g] = out;
    const auto solids = moving_solids(scene);
    const auto owner = moving_solid_of(scene, p);
    // The poses each solid is sampled at, per solid once: 16 over a segment by motion_pose; a
    // motion from a CSV file (many short linear_rotation intervals) at each interval's end, from
    // the start poses (motion_pose over every interval would be quadratic in the rows).
    std::vector<std::vector<RigidPose>> samples(solids.size());
    for (std::size_t j = 0; j < solids.size(); ++j) {
        const Motion& m = solids[j].motion;
        const bool csv = std::any_of(m.segments.begin(), m.segments.end(),
                                     [](const MotionSegment& s) { return s.type == MotionSegment::Type::linear_rotation; });
        const auto starts = csv ? segment_start_poses(m) : std::vector<RigidPose>{};
        for (std::size_t k = 0; k < m.segments.size(); ++k) {
            const auto& s = m.segments[k];
            if (csv) {
                samples[j].push_back(starts[k].then(segment_pose(s, s.end - s.start)));
                continue;
            }
            constexpr int kSamples = 16;
            for (int i = 1; i <= kSamples; ++i) samples[j].push_back(motion_pose(m, s.start + (s.end - s.start) * i / kSamples));
        }
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary) continue;
        q.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
        g.push_back(offsets[i]);
        if (owner[i] < 0) continue;
        for (const RigidPose& pose : samples[static_cast<std::size_t>(owner[i])]) {
            const Vec3 o{offsets[i][0], offsets[i][1], offsets[i][2]};
            const Vec3 turned = RigidPose{pose.R, {0, 0, 0}}.apply(o);
            q.push_back(p.id[i], p.type[i], pose.apply(p.position[i]), p.velocity[i], p.density[i], p.pressure[i]);
            g.push_back({static_cast<float>(turned[0]), static_cast<float>(turned[1]), static_cast<float>(turned[2])});
        }
    }
    return out;
}

}  // namespace clsph::scene
