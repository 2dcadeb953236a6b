// Floating rigid bodies (clsph/scene.hpp, Floating): each floating solid's mass, centre of mass and
// inertia at rest (computed from its particles where the scene gives none), which boundary
// particles belong to which body, and the checks of the scene's floating keys. Pure host code.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph::scene {

struct FloatingBody {
    std::string key;              // "boundaries.boxes[1]", for messages
    std::string name;             // body_NAME.csv
    std::size_t solid = 0;        // index into Scene::solids
    double mass = 0;              // kg
    Vec3 centre{0, 0, 0};         // the centre of mass at rest (m)
    std::array<double, 9> inertia{};  // kg m^2 about the centre, at rest, row-major
    std::size_t count = 0;        // its particles
    std::array<bool, 3> free_translation{true, true, true}, free_rotation{true, true, true};
    Vec3 velocity{0, 0, 0}, angular_velocity{0, 0, 0};  // at t = 0 (m/s, rad/s)
};

// The floating bodies of a scene, in the order of boundaries.boxes.
std::vector<FloatingBody> floating_bodies(const Scene& scene);
// Per particle of p: the index (into floating_bodies) of the body it belongs to, or -1.
std::vector<std::int32_t> floating_body_of(const Scene& scene, const Particles& p);
// The checks of the floating keys (Scene::validate); throws SceneError naming the key.
void check_floating(const Scene& scene);

}  // namespace clsph::scene
