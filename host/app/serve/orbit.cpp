#include "orbit.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace clsph::app::serve {
namespace {

constexpr double pi = 3.14159265358979323846;
double radians(double deg) { return deg * pi / 180.0; }
double degrees(double rad) { return rad * 180.0 / pi; }

// A finite number, the whole text of it (strtod alone takes "1x" as 1 and "nan" as NaN).
std::optional<double> number(const std::string& text) {
    if (text.empty() || text.size() > 32) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

}  // namespace

Orbit home_orbit(const CameraView& home) {
    const double dx = home.eye[0] - home.target[0], dy = home.eye[1] - home.target[1], dz = home.eye[2] - home.target[2];
    Orbit o;
    o.distance = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(o.distance > 0)) o.distance = 1;
    o.azimuth_deg = degrees(std::atan2(dy, dx));
    o.elevation_deg = std::fmax(-max_elevation_deg, std::fmin(max_elevation_deg, degrees(std::asin(dz / o.distance))));
    // The page's default: the scene's aspect at a size that streams well; the page asks for its own.
    o.width = 640;
    o.height = home.width > 0 ? std::max<std::uint32_t>(min_side, static_cast<std::uint32_t>(640.0 * home.height / home.width)) : 360;
    return o;
}

CameraView camera_of(const Orbit& orbit, const CameraView& home) {
    CameraView c = home;
    const double az = radians(orbit.azimuth_deg), el = radians(orbit.elevation_deg);
    c.eye = Vec3{home.target[0] + orbit.distance * std::cos(el) * std::cos(az),
                 home.target[1] + orbit.distance * std::cos(el) * std::sin(az),
                 home.target[2] + orbit.distance * std::sin(el)};
    c.up = Vec3{0, 0, 1};
    c.width = orbit.width;
    c.height = orbit.height;
    return c;
}

OrbitOrError parse_orbit(const std::multimap<std::string, std::string>& params, const Orbit& home, double scene_size) {
    Orbit o = home;
    OrbitOrError out;
    for (const auto& [key, text] : params) {
        if (params.count(key) > 1) {
            out.error = "the camera parameter '" + key + "' is given more than once";
            return out;
        }
        if (key == "colour") {
            if (text == "surface") o.style.surface = SurfaceColour::uniform;
            else if (text == "device") o.style.surface = SurfaceColour::by_device;
            else if (text == "speed") o.style.surface = SurfaceColour::by_speed;
            else if (text == "pressure") o.style.surface = SurfaceColour::by_pressure;
            else {
                out.error = "colour must be surface, device, speed or pressure, got '" + text.substr(0, 40) + "'";
                return out;
            }
            continue;
        }
        const auto v = number(text);
        if (key != "az" && key != "el" && key != "dist" && key != "w" && key != "h" && key != "t" && key != "lo" && key != "hi") {
            out.error = "unknown camera parameter '" + key + "' (az, el, dist, w, h, colour, lo, hi)";
            return out;
        }
        if (!v) {
            out.error = "the camera parameter '" + key + "' must be a finite number, got '" + text.substr(0, 40) + "'";
            return out;
        }
        if (key == "az") {
            o.azimuth_deg = std::remainder(*v, 360.0);
        } else if (key == "el") {
            if (std::fabs(*v) > max_elevation_deg) {
                out.error = "el (elevation) must be within +-89 degrees";
                return out;
            }
            o.elevation_deg = *v;
        } else if (key == "dist") {
            if (!(*v > 1e-6 * scene_size) || *v > 1e3 * scene_size) {
                out.error = "dist (m from the target) must be positive and at most 1000 scene sizes";
                return out;
            }
            o.distance = *v;
        } else if (key == "w" || key == "h") {
            const std::uint32_t limit = key == "w" ? max_width : max_height;
            if (*v != std::floor(*v) || *v < min_side || *v > limit) {
                out.error = key + " (pixels) must be a whole number from " + std::to_string(min_side) + " to " +
                            std::to_string(limit);
                return out;
            }
            (key == "w" ? o.width : o.height) = static_cast<std::uint32_t>(*v);
        } else if (key == "lo") {
            o.style.range_min = *v;  // the colour map's ends (speed m/s, pressure Pa); left out: found
        } else if (key == "hi") {
            o.style.range_max = *v;
        }
        // t: the page's cache buster, any number
    }
    if (std::isfinite(o.style.range_min) && std::isfinite(o.style.range_max) && !(o.style.range_max > o.style.range_min)) {
        out.error = "hi must be greater than lo (the colour map's ends)";
        return out;
    }
    out.orbit = o;
    return out;
}

}  // namespace clsph::app::serve
