// The live view's camera as the page moves it: an orbit about the scene camera's target
// (azimuth, elevation, distance), and the image size; checked before it reaches the devices.
#pragma once
#include <clsph/render.hpp>

#include <map>
#include <optional>
#include <string>

namespace clsph::app::serve {

struct Orbit {
    double azimuth_deg = 0, elevation_deg = 0, distance = 1;  // distance in m from the target
    std::uint32_t width = 640, height = 360;
    ImageStyle style;  // colour=surface|device|speed|pressure, lo=, hi= (the colour map's ends)
};

// The largest image the page may ask for (4K UHD), the smallest, and the elevation limit (the
// view straight down or up has no "up").
constexpr std::uint32_t max_width = 3840, max_height = 2160, min_side = 16;
constexpr double max_elevation_deg = 89.0;

// The orbit that sees what `home` (the scene's camera) sees, at the page's default size.
Orbit home_orbit(const CameraView& home);
// The camera of `orbit` about `home`'s target, with `home`'s field of view.
CameraView camera_of(const Orbit& orbit, const CameraView& home);

// Reads az, el, dist, w, h, colour, lo and hi from the query (any left out: `home`'s); a value that is not a finite
// number, out of range or malformed gives the reason in the user's terms.
struct OrbitOrError {
    std::optional<Orbit> orbit;
    std::string error;
};
OrbitOrError parse_orbit(const std::multimap<std::string, std::string>& params, const Orbit& home, double scene_size);

}  // namespace clsph::app::serve
