#include "device/motion_table.hpp"

#include "scene/lattice_plan.hpp"
#include "scene/motion.hpp"
#include "shared.h"

#include <cmath>
#include <cstring>

namespace clsph::device {

MotionTable motion_table(const Scene& scene, const Grid& grid) {
    MotionTable t;
    const auto solids = scene::moving_solids(scene);
    if (solids.empty()) return t;
    // Boundaries come first in id order, so a plan's boundary particles alone have the scene's ids.
    const Particles boundary = scene::LatticePlan::supports(scene)
                                   ? scene::LatticePlan::make(scene).particles([](const auto&, std::size_t) { return true; }, true)
                                   : scene.build_particles();
    constexpr double two_pi = 6.28318530717958647692;
    for (std::size_t s = 0; s < solids.size(); ++s) {
        // The motion measured from the reference point: axis points shifted, and the start poses
        // of the shifted motion.
        Motion m = solids[s].motion;
        const Vec3 ref = solids[s].reference;
        for (auto& seg : m.segments)
            for (int k = 0; k < 3; ++k) seg.axis_point[k] -= ref[k];
        const auto poses = scene::segment_start_poses(m);
        for (std::size_t i = 0; i < m.segments.size(); ++i) {
            const auto& seg = m.segments[i];
            double row[MotionTable::kSegmentDoubles] = {};
            row[0] = static_cast<double>(seg.type);
            row[1] = seg.start;
            row[2] = seg.end;
            row[3] = static_cast<double>(s);
            for (int k = 0; k < 9; ++k) row[4 + k] = poses[i].R[static_cast<std::size_t>(k)];
            for (int k = 0; k < 3; ++k) row[13 + k] = poses[i].T[static_cast<std::size_t>(k)];
            using Type = MotionSegment::Type;
            const bool turns = seg.type == Type::sine_rotation || seg.type == Type::rotation || seg.type == Type::linear_rotation ||
                               seg.type == Type::ramped_sine_rotation;
            Vec3 v = seg.velocity;
            if (seg.type == Type::sine || seg.type == Type::ramped_sine) v = seg.amplitude;
            if (turns) {
                const double l = std::sqrt(seg.axis[0] * seg.axis[0] + seg.axis[1] * seg.axis[1] + seg.axis[2] * seg.axis[2]);
                v = {seg.axis[0] / l, seg.axis[1] / l, seg.axis[2] / l};
            }
            for (int k = 0; k < 3; ++k) row[16 + k] = v[static_cast<std::size_t>(k)];
            for (int k = 0; k < 3; ++k) row[19 + k] = seg.axis_point[static_cast<std::size_t>(k)];
            row[22] = two_pi / seg.period;
            row[23] = seg.phase;
            row[24] = seg.type == Type::rotation || seg.type == Type::linear_rotation ? seg.angular_velocity : seg.angle;
            if (seg.type == Type::linear_rotation)
                for (int k = 0; k < 3; ++k) row[25 + k] = seg.velocity[static_cast<std::size_t>(k)];
            if (seg.type == Type::ramped_sine || seg.type == Type::ramped_sine_rotation) row[25] = seg.ramp;
            t.segments.insert(t.segments.end(), row, row + MotionTable::kSegmentDoubles);
        }
    }
    const auto owner = scene::moving_solid_of(scene, boundary);
    std::size_t ids = 0;
    for (std::size_t i = 0; i < boundary.size(); ++i)
        if (boundary.type[i] == ParticleType::boundary) ids = std::max<std::size_t>(ids, (boundary.id[i] & CLSPH_ID_MASK) + 1);
    t.rest.assign(4 * ids, 0.0f);
    t.local.assign(4 * ids, 0.0);
    for (std::size_t id = 0; id < ids; ++id) t.local[4 * id + 3] = -1.0;
    for (std::size_t i = 0; i < boundary.size(); ++i) {
        if (boundary.type[i] != ParticleType::boundary || owner[i] < 0) continue;
        const std::size_t id = boundary.id[i] & CLSPH_ID_MASK;
        std::array<float, 3> off{};
        const std::uint32_t key = grid.locate(boundary.position[i], off);
        for (int k = 0; k < 3; ++k) t.rest[4 * id + static_cast<std::size_t>(k)] = off[static_cast<std::size_t>(k)];
        std::memcpy(&t.rest[4 * id + 3], &key, sizeof key);
        const Vec3 ref = solids[static_cast<std::size_t>(owner[i])].reference;
        for (int k = 0; k < 3; ++k)
            t.local[4 * id + static_cast<std::size_t>(k)] = boundary.position[i][static_cast<std::size_t>(k)] - ref[static_cast<std::size_t>(k)];
        t.local[4 * id + 3] = static_cast<double>(owner[i]);
    }
    return t;
}

}  // namespace clsph::device
