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
    merge_k_ = device.kernel("splat.cl", "splat_merge", opts);
}

void Splatter::splat(const CameraView& camera, const device::ParticleArrays& particles, std::size_t first,
                     std::size_t count, double radius, const SplatField& field) {
    const CameraBasis b = camera_basis(camera);
    const std::size_t pixels = std::size_t{camera.width} * camera.height;
    width_ = camera.width;
    height_ = camera.height;
    unit_ = radius * kThicknessUnit;
    has_field_ = field.mode != 0;
    keep_buffer(device_, depth_, pixels * sizeof(cl_uint), "splat depth");
    keep_buffer(device_, thickness_, pixels * sizeof(cl_uint), "splat thickness");
    // The field's sums only when colouring by one (a word of room otherwise: the kernel never touches it).
    keep_buffer(device_, field_, (has_field_ ? pixels : 1) * sizeof(cl_uint), "splat field");
    device_.fill(depth_, cl_uint(0xffffffffu), pixels);
    device_.fill(thickness_, cl_uint(0), pixels);
    device_.fill(field_, cl_uint(0), has_field_ ? pixels : 1);
    if (count == 0) return;
    // The domain's corner relative to the eye, in double: positions are cell + offset from it.
    const auto& lo = grid_.domain().lo;
    const std::array<double, 3> rel{lo[0] - b.eye[0], lo[1] - b.eye[1], lo[2] - b.eye[2]};
    const cl_float4 view{{static_cast<float>(b.scale), static_cast<float>(b.cx), static_cast<float>(b.cy),
                          static_cast<float>(radius)}};
    const cl_uint2 size{{camera.width, camera.height}};
    cl_rt::set_args(splat_k_, first, count, grid_.params(), float4_of(rel), float4_of(b.right), float4_of(b.up), float4_of(b.forward), view,
                    size, static_cast<float>(unit_), cl_uint{field.mode},
                    cl_float2{{static_cast<float>(field.range[0]), static_cast<float>(field.range[1])}}, field.sp,
                    particles.pos, particles.id, particles.velrho, depth_, thickness_, field_);
    device_.launch("splat.particles", splat_k_, count, wg_);
}

SplatImage Splatter::draw(const CameraView& camera, const device::ParticleArrays& particles, std::size_t first,
                          std::size_t count, double radius, const SplatField& field) {
    splat(camera, particles, first, count, radius, field);
    return read();
}

SplatImage Splatter::read() const {
    const std::size_t pixels = std::size_t{width_} * height_;
    SplatImage out;
    out.width = width_;
    out.height = height_;
    out.unit = unit_;
    out.depth.resize(pixels);
    out.thickness.resize(pixels);
    device_.read(depth_, out.depth.data(), pixels);
    device_.read(thickness_, out.thickness.data(), pixels);
    if (has_field_) {
        out.field.resize(pixels);
        device_.read(field_, out.field.data(), pixels);
    }
    return out;
}

void Splatter::merge(const SplatImage& other) {
    const std::size_t pixels = std::size_t{width_} * height_;
    if (other.width != width_ || other.height != height_ || other.unit != unit_ || other.field.empty() == has_field_)
        throw Error("splat: the devices' images differ in size, thickness unit or field");
    if (pixels == 0) return;
    keep_buffer(device_, in_depth_, pixels * sizeof(cl_uint), "splat merged depth");
    keep_buffer(device_, in_thickness_, pixels * sizeof(cl_uint), "splat merged thickness");
    keep_buffer(device_, in_field_, (has_field_ ? pixels : 1) * sizeof(cl_uint), "splat merged field");
    device_.write(in_depth_, other.depth.data(), pixels);
    device_.write(in_thickness_, other.thickness.data(), pixels);
    if (has_field_) device_.write(in_field_, other.field.data(), pixels);
    cl_rt::set_args(merge_k_, cl_rt::checked_uint(pixels), cl_uint{has_field_ ? 1u : 0u}, in_depth_, in_thickness_, in_field_, depth_,
                    thickness_, field_);
    device_.launch("splat.merge", merge_k_, pixels, wg_);
}

}  // namespace clsph::render
