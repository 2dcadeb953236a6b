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
    prepare_k_ = device.kernel("splat_shade.cl", "splat_prepare");
    smooth_k_ = device.kernel("splat_shade.cl", "splat_smooth");
    shade_k_ = device.kernel("splat_shade.cl", "splat_shade");
}

RenderTarget SplatShader::shade(const CameraView& camera, const Splatter& water, const RenderTarget* solids,
                              const Environment& env) {
    const std::size_t pixels = std::size_t{camera.width} * camera.height;
    if (water.width() != camera.width || water.height() != camera.height)
        throw Error("splat: the water's image is not the camera's size");
    if (solids && (solids->width != camera.width || solids->height != camera.height))
        throw Error("splat: the solids' image is not the camera's size");
    const CameraBasis b = camera_basis(camera);
    const cl_uint2 size{{camera.width, camera.height}};
    const bool by_field = water.has_field();
    if (pixels_ != pixels) {  // the buffers kept from frame to frame, released before they are replaced
        pixels_ = 0;
        for (auto* buf : {&depth_a_, &depth_b_, &thick_a_, &thick_b_, &field_, &no_solid_depth_, &no_solid_colour_, &colour_, &out_depth_})
            *buf = {};
        depth_a_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade depth");
        depth_b_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade smoothed depth");
        thick_a_ = device_.alloc(pixels * sizeof(cl_float), "splat shade thickness");
        thick_b_ = device_.alloc(pixels * sizeof(cl_float), "splat shade smoothed thickness");
        field_ = device_.alloc(pixels * sizeof(cl_float), "splat shade field");
        colour_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade colour");
        out_depth_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade out depth");
        pixels_ = pixels;
    }
    if (!solids && !no_solid_depth_) {  // an empty solids' image, once
        no_solid_depth_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade solid depth");
        no_solid_colour_ = device_.alloc(pixels * sizeof(cl_uint), "splat shade solid colour");
        device_.fill(no_solid_depth_, cl_uint(0xffffffffu), pixels);
        device_.fill(no_solid_colour_, cl_uint(0), pixels);
    }
    const cl_rt::Buffer& solid_depth = solids ? *solids->depth : no_solid_depth_;
    const cl_rt::Buffer& solid_colour = solids ? *solids->colour : no_solid_colour_;

    // Counts to metres (the filter blurs the thickness as a float), the field's sums to means.
    cl_rt::set_args(prepare_k_, cl_rt::checked_uint(pixels), static_cast<float>(water.unit()), cl_uint{by_field ? 1u : 0u},
                    water.thickness(), water.field(), thick_a_, field_);
    device_.launch("splat.prepare", prepare_k_, pixels, wg_);

    // Smoothing: the filter reaches kFilterRadii splat radii; depths within kGapRadii blend. The
    // first pass reads the splats' depth where they are; the rest go between the two buffers.
    const cl_float4 filter{{static_cast<float>(b.scale), static_cast<float>(kFilterRadii * env.radius),
                            static_cast<float>(kGapRadii * env.radius), 0.0f}};
    const cl_rt::Buffer* depth_in = &water.depth();
    cl_rt::Buffer* depth_out = &depth_a_;
    cl_rt::Buffer* thick_in = &thick_a_;
    cl_rt::Buffer* thick_out = &thick_b_;
    for (int round = 0; round < kSmoothRounds; ++round)
        for (cl_uint axis = 0; axis < 2; ++axis) {
            cl_rt::set_args(smooth_k_, size, filter, axis, cl_uint(kMaxFilterPx), *depth_in, *thick_in, *depth_out, *thick_out);
            device_.launch("splat.smooth", smooth_k_, pixels, wg_);
            depth_in = depth_out;
            depth_out = depth_out == &depth_a_ ? &depth_b_ : &depth_a_;
            std::swap(thick_in, thick_out);
        }

    const V up = unit(env.up);
    const double eye_height = b.eye[0] * up[0] + b.eye[1] * up[1] + b.eye[2] * up[2] - env.ground;
    const double refract_px = 0.03 * camera.height;
    const cl_float4 view{{static_cast<float>(b.scale), static_cast<float>(b.cx), static_cast<float>(b.cy),
                          static_cast<float>(refract_px)}};
    const cl_float4 edge{{static_cast<float>(0.5 * env.radius), static_cast<float>(20 * env.radius),
                          static_cast<float>(kGapRadii * env.radius), 0.0f}};
    cl_rt::set_args(shade_k_, size, view, float4_of(b.right), float4_of(b.up), float4_of(b.forward), float4_of(b.eye), float4_of(up, eye_height),
                    float4_of(unit(env.sun), env.tile), float4_of(env.absorb), float4_of(env.deep), edge, cl_uint{by_field ? 1u : 0u}, *depth_in,
                    *thick_in, solid_depth, solid_colour, field_, colour_, out_depth_);
    device_.launch("splat.shade", shade_k_, pixels, wg_);

    return {&out_depth_, &colour_, camera.width, camera.height};
}

}  // namespace clsph::render
