// The splats' shading on one device (kernels/splat_shade.cl): the composited depth smoothed by
// two rounds of a separable bilateral filter, then one launch that takes normals from it and shades.
#include "render/splat.hpp"
#include "render/renderer.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clsph::render {
namespace {

using V = std::array<double, 3>;

V unit(const V& v) {
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return l > 0 ? V{v[0] / l, v[1] / l, v[2] / l} : V{0, 0, 1};
}

constexpr int kSmoothRounds = 2;       // x then y, twice
constexpr double kFilterRadii = 4.0;   // the filter's reach in splat radii
constexpr double kGapRadii = 10.0;     // a depth step of this many radii is a silhouette, not a slope
constexpr std::uint32_t kMaxFilterPx = 24;

}  // namespace

SplatShader::SplatShader(cl_rt::Device& device) : device_(device), wg_(device.work_group_size(64)) {
    smooth_k_ = device.kernel("splat_shade.cl", "splat_smooth");
    shade_k_ = device.kernel("splat_shade.cl", "splat_shade");
}

DepthImage SplatShader::shade(const CameraView& camera, const SplatImage& water, const DepthImage& solids,
                              const Environment& env) {
    const std::size_t pixels = std::size_t{camera.width} * camera.height;
    if (water.width != camera.width || water.height != camera.height || water.depth.size() != pixels)
        throw Error("splat: the water's image is not the camera's size");
    const bool have_solids = !solids.depth.empty();
    if (have_solids && solids.depth.size() != pixels) throw Error("splat: the solids' image is not the camera's size");
    const CameraBasis b = camera_basis(camera);
    const cl_uint2 size{{camera.width, camera.height}};

    auto depth_a = device_.alloc(pixels * sizeof(cl_uint), "splat shade depth");
    auto depth_b = device_.alloc(pixels * sizeof(cl_uint), "splat shade smoothed depth");
    auto thick = device_.alloc(pixels * sizeof(cl_float), "splat shade thickness");
    auto thick_b = device_.alloc(pixels * sizeof(cl_float), "splat shade smoothed thickness");
    auto solid_depth = device_.alloc(pixels * sizeof(cl_uint), "splat shade solid depth");
    auto solid_colour = device_.alloc(pixels * sizeof(cl_uint), "splat shade solid colour");
    auto colour = device_.alloc(pixels * sizeof(cl_uint), "splat shade colour");
    auto out_depth = device_.alloc(pixels * sizeof(cl_uint), "splat shade out depth");
    // Coloured by a field: each pixel's chord-weighted mean t (-1 without water).
    const bool by_field = !water.field.empty();
    auto field = device_.alloc((by_field ? pixels : 1) * sizeof(cl_float), "splat shade field");
    if (by_field) {
        std::vector<float> t(pixels, -1.0f);
        for (std::size_t p = 0; p < pixels; ++p)
            if (water.thickness[p] > 0) t[p] = static_cast<float>(static_cast<double>(water.field[p]) / water.thickness[p]);
        device_.write(field, t.data(), pixels);
    } else {
        device_.fill(field, cl_float(-1.0f), 1);
    }
    device_.write(depth_a, water.depth.data(), pixels);
    std::vector<float> metres(pixels);  // counts to metres: the filter blurs the thickness as a float
    for (std::size_t p = 0; p < pixels; ++p) metres[p] = static_cast<float>(water.thickness[p] * water.unit);
    device_.write(thick, metres.data(), pixels);
    if (have_solids) {
        device_.write(solid_depth, solids.depth.data(), pixels);
        device_.write(solid_colour, solids.colour.data(), pixels);
    } else {
        device_.fill(solid_depth, cl_uint(0xffffffffu), pixels);
        device_.fill(solid_colour, cl_uint(0), pixels);
    }

    // Smoothing: the filter reaches kFilterRadii splat radii; depths within kGapRadii blend.
    const cl_float4 filter{{static_cast<float>(b.scale), static_cast<float>(kFilterRadii * env.radius),
                            static_cast<float>(kGapRadii * env.radius), 0.0f}};
    for (int round = 0; round < kSmoothRounds; ++round)
        for (cl_uint axis = 0; axis < 2; ++axis) {
            cl_rt::set_args(smooth_k_, size, filter, axis, cl_uint(kMaxFilterPx), depth_a, thick, depth_b, thick_b);
            device_.launch("splat.smooth", smooth_k_, pixels, wg_);
            std::swap(depth_a, depth_b);
            std::swap(thick, thick_b);
        }

    const V up = unit(env.up);
    const double eye_height = b.eye[0] * up[0] + b.eye[1] * up[1] + b.eye[2] * up[2] - env.ground;
    const double refract_px = 0.03 * camera.height;
    const cl_float4 view{{static_cast<float>(b.scale), static_cast<float>(b.cx), static_cast<float>(b.cy),
                          static_cast<float>(refract_px)}};
    const cl_float4 edge{{static_cast<float>(0.5 * env.radius), static_cast<float>(20 * env.radius),
                          static_cast<float>(kGapRadii * env.radius), 0.0f}};
    cl_rt::set_args(shade_k_, size, view, float4_of(b.right), float4_of(b.up), float4_of(b.forward), float4_of(b.eye), float4_of(up, eye_height),
                    float4_of(unit(env.sun), env.tile), float4_of(env.absorb), float4_of(env.deep), edge, cl_uint{by_field ? 1u : 0u}, depth_a, thick,
                    solid_depth, solid_colour, field, colour, out_depth);
    device_.launch("splat.shade", shade_k_, pixels, wg_);

    return read_depth_image(device_, out_depth, colour, camera.width, camera.height);
}

}  // namespace clsph::render
