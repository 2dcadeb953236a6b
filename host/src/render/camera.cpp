#include "clsph/render.hpp"

#include "scene/mesh.hpp"
#include "scene/mesh_formats.hpp"

#include <algorithm>
#include <cmath>

namespace clsph {
namespace {

struct Bounds {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    bool empty() const { return !(lo[0] <= hi[0]); }
    void add(const Vec3& a, const Vec3& b) {
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], std::min(a[k], b[k]));
            hi[k] = std::max(hi[k], std::max(a[k], b[k]));
        }
    }
};

// What the picture is of: the fluid's blocks and meshes, the tank's walls and the solid boxes
// (the domain's margins and empty air left out); the domain when the scene names none of them.
Bounds subject_of(const Scene& scene) {
    Bounds b;
    for (const auto& f : scene.fluids) b.add(f.min, f.max);
    for (const auto& w : scene.walls) b.add(w.min, w.max);
    for (const auto& s : scene.solids) b.add(s.min, s.max);
    for (const auto& m : scene.meshes) {
        try {
            scene::TriangleMesh mesh = scene::read_mesh(m.path);
            scene::place_mesh(mesh, m);
            for (const auto& x : mesh.vertices) b.add(x, x);
        } catch (const std::exception&) {
            b.add(scene.domain.min, scene.domain.max);  // unreadable here: frame the domain
        }
    }
    Bounds domain;
    domain.add(scene.domain.min, scene.domain.max);
    if (b.empty()) return domain;
    for (std::size_t k = 0; k < 3; ++k) {  // within the domain
        b.lo[k] = std::max(b.lo[k], domain.lo[k]);
        b.hi[k] = std::min(b.hi[k], domain.hi[k]);
    }
    return b.empty() ? domain : b;
}

}  // namespace

CameraView camera_for(const Scene& scene) {
    CameraView c;
    c.width = scene.render.width;
    c.height = scene.render.height;
    if (scene.render.has_camera) {
        c.eye = scene.render.eye;
        c.target = scene.render.target;
        c.up = scene.render.up;
        c.fov_deg = scene.render.fov_deg;
        return c;
    }
    // Frame the subject: look at its centre from the front left and above (z up), as near as lets
    // every corner of its box into the picture with a 5 % margin.
    const Bounds s = subject_of(scene);
    Vec3 centre{};
    for (std::size_t k = 0; k < 3; ++k) centre[k] = 0.5 * (s.lo[k] + s.hi[k]);
    const double pi = 3.14159265358979323846;
    const double tan_v = std::tan(0.5 * c.fov_deg * pi / 180.0) * 0.95;
    const double tan_h = tan_v * static_cast<double>(c.width) / static_cast<double>(c.height);
    const double az = -60.0 * pi / 180.0, el = 25.0 * pi / 180.0;
    const Vec3 dir{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};  // centre to eye
    // The camera's right and up (forward = -dir, world up z).
    const Vec3 right{-dir[1] / std::hypot(dir[0], dir[1]), dir[0] / std::hypot(dir[0], dir[1]), 0.0};
    const Vec3 up{dir[1] * right[2] - dir[2] * right[1], dir[2] * right[0] - dir[0] * right[2],
                  dir[0] * right[1] - dir[1] * right[0]};
    double distance = 0;
    for (int corner = 0; corner < 8; ++corner) {
        Vec3 rel{};
        for (std::size_t k = 0; k < 3; ++k) rel[k] = ((corner >> k) & 1 ? s.hi[k] : s.lo[k]) - centre[k];
        const double along = rel[0] * dir[0] + rel[1] * dir[1] + rel[2] * dir[2];
        const double r = std::abs(rel[0] * right[0] + rel[1] * right[1] + rel[2] * right[2]);
        const double u = std::abs(rel[0] * up[0] + rel[1] * up[1] + rel[2] * up[2]);
        // The corner's depth is distance - along; it must be at least r / tan_h and u / tan_v.
        distance = std::max({distance, along + r / tan_h, along + u / tan_v});
    }
    if (!(distance > 0)) distance = 1.0;
    for (std::size_t k = 0; k < 3; ++k) c.eye[k] = centre[k] + distance * dir[k];
    c.target = centre;
    c.up = {0, 0, 1};
    return c;
}

}  // namespace clsph
