// Prescribed motion of solids (clsph/scene.hpp, Motion) in closed form, in double precision: the
// pose of a solid at a time, a point's velocity, and which boundary particles belong to which
// moving solid. Pure host code: the devices evaluate the same formulas from a table of segments
// (device/motion_table.hpp, kernels/motion.cl); the tests compare the two.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace clsph::scene {

// A rigid transform x -> R x + T (R row-major).
struct RigidPose {
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    Vec3 T{0, 0, 0};
    Vec3 apply(const Vec3& x) const;
    RigidPose then(const RigidPose& next) const;  // next after this
};

// A segment's rigid transform after tau = t - start seconds of it (tau in [0, end - start]): the
// point y where the segment found it moves to segment_pose(s, tau).apply(y).
RigidPose segment_pose(const MotionSegment& s, double tau);
// The pose of a solid at time t: a particle resting at x0 is at pose.apply(x0).
RigidPose motion_pose(const Motion& m, double t);
// Per segment, the pose it starts from (the segments before it, complete).
std::vector<RigidPose> segment_start_poses(const Motion& m);
// The velocity at time t of the particle resting at x0 (zero outside every segment).
Vec3 motion_velocity(const Motion& m, double t, const Vec3& x0);

// The moving solids of a scene, in the order walls, boxes, meshes (a solid without motion is
// left out), each with its motion and a reference point (the centre of its extent) the device
// table measures positions from.
struct MovingSolid {
    Motion motion;
    Vec3 reference{0, 0, 0};
    std::string key;                 // "boundaries.boxes[1]", for messages
};
std::vector<MovingSolid> moving_solids(const Scene& scene);
// Per particle of p: the index (into moving_solids) of the moving solid it belongs to, or -1
// (fluid, static boundaries). Recognised by lattice point, as ghost nodes are.
std::vector<std::int32_t> moving_solid_of(const Scene& scene, const Particles& p);

// mDBC with several devices (multi::Partition::restrict_cuts): the boundary particles of p with
// their ghost-node offsets, and besides them every moving particle at 16 times over each segment
// of its motion, its offset turned with it: where the solid's ghost nodes will be.
std::pair<Particles, std::vector<std::array<float, 3>>> swept_ghost_nodes(const Scene& scene, const Particles& p,
                                                                          const std::vector<std::array<float, 3>>& offsets);

}  // namespace clsph::scene
