// Images of a simulation, rendered by its devices: the free surface (clsph/mesh.hpp) shaded by its
// normals, solid boxes drawn grey, the tank's walls as lines, from a camera that frames the domain
// unless the scene gives one (render.camera, render.size: docs/scenes.md). PNG files through libpng.
#pragma once
#include "clsph/scene.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace clsph {

struct CameraView {
    Vec3 eye{0, 0, 0}, target{0, 0, 0}, up{0, 0, 1};
    double fov_deg = 40.0;  // vertical field of view
    std::uint32_t width = 1280, height = 720;
};

// How an image colours the water: one colour, each device's slab its own (the paper's Fig. 5:
// which device owns which part of the fluid, as the balancer moves the cuts), or by a field of the
// fluid particles through a colour map (field_colour): their speed |v| (m/s) or their pressure
// (Pa, by the run's equation of state, Tait: B ((rho / rho0)^7 - 1)). Both render methods: the
// surface's vertices take the Shepard average of the particles within the kernel's support, a
// splat pixel the mean along its ray through the water weighted by the chord through each sphere.
// by_device colours surfaces only (render.method "splat" draws it as uniform).
enum class SurfaceColour { uniform, by_device, by_speed, by_pressure };
struct ImageStyle {
    SurfaceColour surface = SurfaceColour::uniform;
    // by_speed, by_pressure: the field's values at the colour map's ends (range_min at t = 0). NaN
    // (either): from the state now, on the devices: speeds from 0 to the greatest fluid speed,
    // pressures from the least to the greatest fluid pressure. Image::range says what was used.
    double range_min = std::numeric_limits<double>::quiet_NaN();
    double range_max = std::numeric_limits<double>::quiet_NaN();
};
inline bool by_field(SurfaceColour c) { return c == SurfaceColour::by_speed || c == SurfaceColour::by_pressure; }

// The colour of device d's slab with SurfaceColour::by_device (RGB, 0..1; repeats after 8).
std::array<float, 3> device_colour(std::size_t d);
// The colour map of by_speed and by_pressure: t in [0, 1] (range_min to range_max; clamped) to
// RGB 0..1, dark blue - blue - green - yellow - red (kernels/colour_map.h, as the devices use it).
std::array<float, 3> field_colour(double t);

// The scene's render.camera and render.size, or a camera that frames the whole domain from the
// front left and above.
CameraView camera_for(const Scene& scene);

struct Image {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // 3 bytes a pixel, rows from the top
    // Coloured by a field: the values at the colour map's ends (ImageStyle's, or found); else NaN.
    std::array<double, 2> range{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

// PNG, 8-bit RGB; errors name the path.
void write_png(const std::string& path, const Image& image);
Image read_png(const std::string& path);

}  // namespace clsph
