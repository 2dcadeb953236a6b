// The device's form of the scene's prescribed motions (kernels/motion.cl): a table of segments,
// each with the pose its solid starts it from, and per boundary id the particle's rest position
// (cell key and offset, as the particle store holds it) and its position relative to its solid's
// reference point with the solid's index. Pure C++: built on the host from the scene's boundary
// particles (scene/motion.hpp), uploaded once by Physics::set_motion.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"

#include <cstddef>
#include <vector>

namespace clsph::device {

struct MotionTable {
    // Doubles per segment: type, start, end, solid, the start pose's R (9, row-major) and T (3),
    // the segment's vector (velocity, amplitude or the unit axis), its axis point, omega =
    // 2 pi / period, phase, and the angle amplitude or the angular velocity; then the
    // linear_rotation's velocity (3) or a ramped segment's ramp time; all positions relative to the
    // solid's reference point. The segments of a solid are consecutive and in increasing start,
    // the solids in increasing index: the kernel finds a segment by binary search.
    static constexpr std::size_t kSegmentDoubles = 28;
    std::vector<double> segments;
    std::vector<float> rest;    // per boundary id: offset x, y, z, key bits
    std::vector<double> local;  // per boundary id: position - reference, solid index (-1: still)
    std::size_t segment_count() const { return segments.size() / kSegmentDoubles; }
    std::size_t ids() const { return rest.size() / 4; }
    bool empty() const { return segments.empty(); }
};

// The table of a scene, from its own boundary particles at rest (ids are stable over a run, so
// it serves a run resumed from a checkpoint, whose solids have moved, as well).
MotionTable motion_table(const Scene& scene, const Grid& grid);

}  // namespace clsph::device
