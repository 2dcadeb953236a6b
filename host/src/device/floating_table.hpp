// The device's form of the floating bodies (host/src/multi/rigid_bodies.hpp, kernels/floating.cl):
// per boundary id the particle's offset from its body's centre at rest and the body's index (-1:
// not a floating body), and in the motion table (device/motion_table.hpp) a row per body of type
// 7, "the pose the host supplies", which the host rewrites before each move of the solids
// (Physics::set_floating_poses). Pure C++.
#pragma once
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "device/motion_table.hpp"

#include <cstddef>
#include <vector>

namespace clsph::device {

constexpr double kFloatingSegmentType = 7;  // after MotionSegment::Type's (kernels/motion.cl)

struct FloatingTable {
    std::vector<float> body_rest;  // per boundary id: r0 x, y, z, body index (-1: none)
    std::size_t bodies = 0;
    std::size_t first_row = 0;     // the first body's row in the motion table
    std::size_t ids() const { return body_rest.size() / 4; }
};

// Appends the scene's floating bodies to `motion` (rows at rest, and each body particle's rest
// position and offset from the body's centre, as a moving solid's), and returns their table.
FloatingTable add_floating(MotionTable& motion, const Scene& scene, const Grid& grid);

}  // namespace clsph::device
