// Images of a simulation, rendered by its devices: the free surface (clsph/mesh.hpp) shaded by its
// normals, solid boxes drawn grey, the tank's walls as lines, from a camera that frames the domain
// unless the scene gives one (render.camera, render.size: docs/scenes.md). PNG files through libpng.
#pragma once
#include "clsph/scene.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph {

struct CameraView {
    Vec3 eye{0, 0, 0}, target{0, 0, 0}, up{0, 0, 1};
    double fov_deg = 40.0;  // vertical field of view
    std::uint32_t width = 1280, height = 720;
};

// How an image colours the free surface: one colour, or each device's slab its own (the paper's
// Fig. 5: which device owns which part of the fluid, as the balancer moves the cuts).
enum class SurfaceColour { uniform, by_device };
struct ImageStyle {
    SurfaceColour surface = SurfaceColour::uniform;
};

// The colour of device d's slab with SurfaceColour::by_device (RGB, 0..1; repeats after 8).
std::array<float, 3> device_colour(std::size_t d);

// The scene's render.camera and render.size, or a camera that frames the whole domain from the
// front left and above.
CameraView camera_for(const Scene& scene);

struct Image {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // 3 bytes a pixel, rows from the top
};

// PNG, 8-bit RGB; errors name the path.
void write_png(const std::string& path, const Image& image);
Image read_png(const std::string& path);

}  // namespace clsph
