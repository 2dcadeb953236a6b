#include "device/floating_table.hpp"

#include "scene/floating.hpp"
#include "scene/lattice_plan.hpp"
#include "scene/motion.hpp"
#include "shared.h"

#include <algorithm>
#include <cstring>

namespace clsph::device {

FloatingTable add_floating(MotionTable& t, const Scene& scene, const Grid& grid) {
    FloatingTable out;
    const auto bodies = scene::floating_bodies(scene);
    if (bodies.empty()) return out;
    const std::size_t moving = scene::moving_solids(scene).size();  // the prescribed ones come first
    out.bodies = bodies.size();
    out.first_row = t.segment_count();
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        double row[MotionTable::kSegmentDoubles] = {};
        row[0] = kFloatingSegmentType;
        row[1] = -1e30;  // always the body's segment
        row[2] = 1e30;
        row[3] = static_cast<double>(moving + b);
        row[4] = row[8] = row[12] = 1.0;  // at rest: R = 1, T = V = W = 0
        t.segments.insert(t.segments.end(), row, row + MotionTable::kSegmentDoubles);
    }
    // Boundaries come first in id order, so a plan's boundary particles alone have the scene's ids.
    const Particles boundary = scene::LatticePlan::supports(scene)
                                   ? scene::LatticePlan::make(scene).particles([](const auto&, std::size_t) { return true; }, true)
                                   : scene.build_particles();
    const auto owner = scene::floating_body_of(scene, boundary);
    std::size_t ids = t.ids();
    for (std::size_t i = 0; i < boundary.size(); ++i)
        if (boundary.type[i] == ParticleType::boundary) ids = std::max<std::size_t>(ids, (boundary.id[i] & CLSPH_ID_MASK) + 1);
    const std::size_t had = t.ids();
    t.rest.resize(4 * ids, 0.0f);
    t.local.resize(4 * ids, 0.0);
    for (std::size_t id = had; id < ids; ++id) t.local[4 * id + 3] = -1.0;
    out.body_rest.assign(4 * ids, 0.0f);
    for (std::size_t id = 0; id < ids; ++id) out.body_rest[4 * id + 3] = -1.0f;
    for (std::size_t i = 0; i < boundary.size(); ++i) {
        if (boundary.type[i] != ParticleType::boundary || owner[i] < 0) continue;
        const std::size_t id = boundary.id[i] & CLSPH_ID_MASK;
        const auto& body = bodies[static_cast<std::size_t>(owner[i])];
        std::array<float, 3> off{};
        const std::uint32_t key = grid.locate(boundary.position[i], off);
        for (std::size_t k = 0; k < 3; ++k) {
            t.rest[4 * id + k] = off[k];
            const double r0 = boundary.position[i][k] - body.centre[k];
            t.local[4 * id + k] = r0;
            out.body_rest[4 * id + k] = static_cast<float>(r0);
        }
        std::memcpy(&t.rest[4 * id + 3], &key, sizeof key);
        t.local[4 * id + 3] = static_cast<double>(moving + static_cast<std::size_t>(owner[i]));
        out.body_rest[4 * id + 3] = static_cast<float>(owner[i]);
    }
    return out;
}

}  // namespace clsph::device
