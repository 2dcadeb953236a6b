// Screen-space fluid rendering (render.method "splat", docs/scenes.md): no mesh. Each device
// splats its own fluid particles as spheres into a depth image and a thickness image
// (kernels/splat.cl); the host composites the devices' images (nearest depth, summed thickness:
// only images cross devices); one device smooths the depth, takes normals from it and shades the
// water over the solids, the ground and the sky (kernels/splat_shade.cl).
#pragma once
#include "cl/device.hpp"
#include "clsph/render.hpp"
#include "device/grid.hpp"
#include "device/particle_arrays.hpp"
#include "render/renderer.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::render {

// Splat radius in particle spacings (spheres on a lattice of dp overlap a little, so the water has
// no holes between them), and the metres of one thickness count in sphere radii.
constexpr double kSplatRadius = 0.6;
constexpr double kThicknessUnit = 1.0 / 1024;

struct SplatImage {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint32_t> depth;      // bits of a positive float (along forward); all ones: none
    std::vector<std::uint32_t> thickness;  // chord lengths summed, in counts of `unit` metres
    // Coloured by a field: t in [0, 1] times the chord, summed in the thickness's counts (so the
    // chord-weighted mean along the ray is field / thickness); empty otherwise.
    std::vector<std::uint32_t> field;
    double unit = 0;
};

// What a splat pass colours by: the kernels' mode (render/field.hpp field_mode; 0: nothing) and the
// field's values at t = 0 and 1.
struct SplatField {
    std::uint32_t mode = 0;
    std::array<double, 2> range{0, 0};
    SphParams sp{};
};

// The splat pass on one device: depth and thickness images of particles [first, first + count)
// of `particles` (boundary particles and particles with the invalid key skipped). The images stay
// in the Splatter's buffers (kept from frame to frame, reallocated only when the camera's size
// changes) until the next splat: `draw` reads them back, `splat` leaves them there for the shading
// on this device (SplatShader::shade), other devices' images merged in by `merge`.
class Splatter {
public:
    Splatter(cl_rt::Device& device, const device::Grid& grid);
    SplatImage draw(const CameraView& camera, const device::ParticleArrays& particles, std::size_t first,
                    std::size_t count, double radius, const SplatField& field = {});
    void splat(const CameraView& camera, const device::ParticleArrays& particles, std::size_t first, std::size_t count,
               double radius, const SplatField& field = {});
    // The images of the last splat, read back.
    SplatImage read() const;
    // Another device's image (read back from there) merged into this one's: nearest depth, sums added.
    void merge(const SplatImage& other);

    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }
    double unit() const { return unit_; }
    bool has_field() const { return has_field_; }
    const cl_rt::Buffer& depth() const { return depth_; }
    const cl_rt::Buffer& thickness() const { return thickness_; }
    const cl_rt::Buffer& field() const { return field_; }

private:
    cl_rt::Device& device_;
    const device::Grid& grid_;
    cl::Kernel splat_k_, merge_k_;
    std::size_t wg_;
    cl_rt::Buffer depth_, thickness_, field_, in_depth_, in_thickness_, in_field_;
    std::uint32_t width_ = 0, height_ = 0;
    double unit_ = 0;
    bool has_field_ = false;
};

// Where the picture sits in the world, for the shading: which way is up (against gravity), the
// ground plane's height along it, the checker's tile, the sun, the water's absorption.
struct Environment {
    Vec3 up{0, 0, 1};
    double ground = 0;              // the ground plane: points x with dot(x, up) == ground
    double tile = 0.1;              // m
    Vec3 sun{0.35, -0.45, 0.82};    // towards the sun (normalised where used)
    std::array<double, 3> absorb{6.0, 1.8, 0.9};  // per metre, red absorbed most
    std::array<double, 3> deep{0.03, 0.22, 0.33};  // the colour deep water tends to
    double radius = 0.01;           // the splats' radius, m (the filter's and the rim's scale)
};

// Smoothing, normals and shading on one device: the water of `water` over `solids` (the solids'
// depth and colour, from Renderer::render on this device; null: none), the ground and the sky. The
// result's depth is the water's, the solids' or the ground's (for the walls' lines drawn after).
// Where `water` has a field, the water takes the colour map's colour of its mean t. The water's
// images are the Splatter's on this device: nothing but the result crosses to the host. The
// buffers are kept from frame to frame.
class SplatShader {
public:
    explicit SplatShader(cl_rt::Device& device);
    // The picture, left on the device (valid until the next shade).
    RenderTarget shade(const CameraView& camera, const Splatter& water, const RenderTarget* solids, const Environment& env);

private:
    cl_rt::Device& device_;
    cl::Kernel prepare_k_, smooth_k_, shade_k_;
    std::size_t wg_;
    std::size_t pixels_ = 0;
    cl_rt::Buffer depth_a_, depth_b_, thick_a_, thick_b_, field_, no_solid_depth_, no_solid_colour_, colour_, out_depth_;
};

// Device bytes per pixel: of the splat pass on each device, and of the shading on its device.
constexpr std::size_t kSplatBytesPerPixel = 8;
constexpr std::size_t kShadeBytesPerPixel = 32;

}  // namespace clsph::render
