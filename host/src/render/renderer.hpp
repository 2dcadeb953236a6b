// Rasterising triangle meshes on one device (kernels/render.cl): a depth buffer and a colour buffer
// of the camera's size, layers of triangles drawn into them in turn, both read back for the host
// to composite several devices' images by depth.
#pragma once
#include "cl/device.hpp"
#include "clsph/mesh.hpp"
#include "clsph/render.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::render {

struct Layer {
    const TriangleMesh* mesh = nullptr;
    std::vector<std::uint32_t> triangles;  // indices into mesh->triangles to draw (empty: none)
    std::array<float, 3> colour{0.3f, 0.55f, 0.9f};
};

// Triangles already on the renderer's device: float4 positions and normals, 3 uint vertex indices
// per triangle (the free surface as the devices made it: surface/device_surface.hpp).
struct DeviceLayer {
    const cl_rt::Buffer* positions = nullptr;
    const cl_rt::Buffer* normals = nullptr;
    const cl_rt::Buffer* triangles = nullptr;
    std::size_t count = 0;  // triangles (with `live`: at most this many)
    std::array<float, 3> colour{0.3f, 0.55f, 0.9f};
    // Where the device holds the number of triangles (a surface's totals, surface/device_surface.hpp):
    // (*live)[live_at] for live_at < 4; null: `count`.
    const cl_rt::Buffer* live = nullptr;
    std::uint32_t live_at = 4;
    // Per vertex a field's t in [0, 1] for the colour map (render/field.hpp; below 0: `colour`); null: `colour`.
    const cl_rt::Buffer* values = nullptr;
};

// The camera as the kernels take it: the eye, three unit axes (right, up, forward) and the image
// plane's scale (pixels per unit of x / z) and centre.
struct CameraBasis {
    std::array<double, 3> eye, right, up, forward;
    double scale, cx, cy;
};
CameraBasis camera_basis(const CameraView& camera);

// `b` at least `bytes` long, its contents undefined: kept when it is, else released, then
// allocated (the images' buffers, kept from frame to frame).
void keep_buffer(cl_rt::Device& device, cl_rt::Buffer& b, std::size_t bytes, const char* what);

// A vector (and w) as the kernels' float4.
cl_float4 float4_of(const std::array<double, 3>& v, double w = 0);

struct DepthImage {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint32_t> depth;   // bits of a positive float; all ones where nothing is
    std::vector<std::uint32_t> colour;  // RGBA8 packed, R lowest
};

// A depth and a colour buffer of width x height pixels read back into a DepthImage (blocking).
DepthImage read_depth_image(cl_rt::Device& device, const cl_rt::Buffer& depth, const cl_rt::Buffer& colour,
                            std::uint32_t width, std::uint32_t height);

// A host mesh's layer uploaded to a device (Renderer::upload).
struct UploadedLayer {
    cl_rt::Buffer positions, normals, triangles;
    std::size_t count = 0;
    std::array<float, 3> colour{};
    DeviceLayer layer() const { return {&positions, &normals, &triangles, count, colour}; }
};

// A depth and a colour image on a device (the Renderer's, kept from frame to frame).
struct RenderTarget {
    const cl_rt::Buffer* depth = nullptr;
    const cl_rt::Buffer* colour = nullptr;
    std::uint32_t width = 0, height = 0;
};

class Renderer {
public:
    explicit Renderer(cl_rt::Device& device);
    // The layer's triangles on this device, to draw beside triangles already there.
    UploadedLayer upload(const Layer& layer);
    DepthImage draw(const CameraView& camera, const std::vector<Layer>& layers);
    // The same for triangles already on the device, drawn as they are (nothing uploaded).
    DepthImage draw(const CameraView& camera, const std::vector<DeviceLayer>& layers);
    // The same, the image left on the device (valid until the next render or draw).
    RenderTarget render(const CameraView& camera, const std::vector<DeviceLayer>& layers);

private:
    cl_rt::Device& device_;
    cl::Kernel depth_k_, shade_k_, shade_field_k_;
    std::size_t wg_;
    cl_rt::Buffer depth_, colour_;  // kept from frame to frame, reallocated when the size changes
    cl_rt::Buffer no_live_;         // four zeros: the `live` argument of layers counted on the host
};

// The nearest of several depth images, pixel by pixel, over `background` (the walls' lines are
// drawn by the caller); ties keep the first image's colour.
DepthImage composite(const std::vector<DepthImage>& images);

// The pixels lines cover (a pixel of the camera's image, row-major, and the depth its line has
// there, as bits of a float, a little in front of a face the line lies on), in order.
struct LinePixel {
    std::uint32_t index = 0, depth = 0;
};
std::vector<LinePixel> line_pixels(const CameraView& camera, const std::vector<std::array<Vec3, 2>>& lines);
// Lines drawn into the image with the depth test (wireframes of the walls).
void draw_lines(DepthImage& image, const CameraView& camera, const std::vector<std::array<Vec3, 2>>& lines,
                std::array<std::uint8_t, 3> rgb);

Image to_rgb(const DepthImage& image, std::array<std::uint8_t, 3> background);

}  // namespace clsph::render
