#include "render/splat.hpp"

#include "render/renderer.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>

namespace clsph::render {
Splatter::Splatter(cl_rt::Device& device, const device::Grid& grid)
    : device_(device), grid_(grid), wg_(device.work_group_size(64)) {
    std::string opts = grid.kernel_options();
    if (device.quirks().atomic_min_unreliable) opts += " -DCLSPH_DEPTH_BY_CAS";
    splat_k_ = device.kernel("splat.cl", "splat_particles", opts);
}

SplatImage Splatter::draw(const CameraView& camera, const device::ParticleArrays& particles, std::size_t first,
                          std::size_t count, double radius, const SplatField& field) {
    const CameraBasis b = camera_basis(camera);
    const std::size_t pixels = std::size_t{camera.width} * camera.height;
    SplatImage out;
    out.width = camera.width;
    out.height = camera.height;
    out.unit = radius * kThicknessUnit;
    auto depth = device_.alloc(pixels * sizeof(cl_uint), "splat depth");
    auto thickness = device_.alloc(pixels * sizeof(cl_uint), "splat thickness");
    device_.fill(depth, cl_uint(0xffffffffu), pixels);
    device_.fill(thickness, cl_uint(0), pixels);
    // The field's sums only when colouring by one (a word of room otherwise: the kernel never touches it).
    auto field_sum = device_.alloc((field.mode ? pixels : 1) * sizeof(cl_uint), "splat field");
    device_.fill(field_sum, cl_uint(0), field.mode ? pixels : 1);
    if (count > 0) {
        // The domain's corner relative to the eye, in double: positions are cell + offset from it.
        const auto& lo = grid_.domain().lo;
        const std::array<double, 3> rel{lo[0] - b.eye[0], lo[1] - b.eye[1], lo[2] - b.eye[2]};
        const cl_float4 view{{static_cast<float>(b.scale), static_cast<float>(b.cx), static_cast<float>(b.cy),
                              static_cast<float>(radius)}};
        const cl_uint2 size{{camera.width, camera.height}};
        cl_rt::set_args(splat_k_, first, count, grid_.params(), float4_of(rel), float4_of(b.right), float4_of(b.up), float4_of(b.forward), view,
                        size, static_cast<float>(out.unit), cl_uint{field.mode},
                        cl_float2{{static_cast<float>(field.range[0]), static_cast<float>(field.range[1])}}, field.sp,
                        particles.pos, particles.id, particles.velrho, depth, thickness, field_sum);
        device_.launch("splat.particles", splat_k_, count, wg_);
    }
    out.depth.resize(pixels);
    out.thickness.resize(pixels);
    device_.read(depth, out.depth.data(), pixels);
    device_.read(thickness, out.thickness.data(), pixels);
    if (field.mode) {
        out.field.resize(pixels);
        device_.read(field_sum, out.field.data(), pixels);
    }
    return out;
}

SplatImage composite(const std::vector<SplatImage>& images) {
    if (images.empty()) throw Error("splat: nothing to composite");
    SplatImage out = images.front();
    for (std::size_t i = 1; i < images.size(); ++i) {
        const auto& im = images[i];
        if (im.width != out.width || im.height != out.height || im.unit != out.unit || im.field.size() != out.field.size())
            throw Error("splat: the devices' images differ in size, thickness unit or field");
        for (std::size_t p = 0; p < out.depth.size(); ++p) {
            out.depth[p] = std::min(out.depth[p], im.depth[p]);
            out.thickness[p] += im.thickness[p];
        }
        for (std::size_t p = 0; p < out.field.size(); ++p) out.field[p] += im.field[p];
    }
    return out;
}

}  // namespace clsph::render
