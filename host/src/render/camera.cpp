#include "clsph/render.hpp"

#include <algorithm>
#include <cmath>

namespace clsph {

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
    // Frame the domain: look at its centre from the front left and above (z up), far enough that
    // its bounding sphere fits the narrower field of view.
    const auto& lo = scene.domain.min;
    const auto& hi = scene.domain.max;
    Vec3 centre{}, half{};
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5 * (lo[k] + hi[k]);
        half[k] = 0.5 * (hi[k] - lo[k]);
    }
    const double radius = std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
    const double pi = 3.14159265358979323846;
    const double vfov = c.fov_deg * pi / 180.0;
    const double hfov = 2 * std::atan(std::tan(vfov / 2) * c.width / c.height);
    const double distance = 1.05 * radius / std::sin(0.5 * std::min(vfov, hfov));
    const double az = -60.0 * pi / 180.0, el = 25.0 * pi / 180.0;
    const Vec3 dir{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
    for (int k = 0; k < 3; ++k) c.eye[k] = centre[k] + distance * dir[k];
    c.target = centre;
    c.up = {0, 0, 1};
    return c;
}

}  // namespace clsph
