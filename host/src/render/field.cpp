#include "render/field.hpp"

#include "multi/ranks.hpp"

#include "render/renderer.hpp"

#include "cl/kernel_args.hpp"
#include "colour_map.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace clsph {

std::array<float, 3> field_colour(double t) {
    std::array<float, 3> c{};
    clsph_colour_map(static_cast<float>(t), &c[0], &c[1], &c[2]);
    return c;
}

}  // namespace clsph

namespace clsph::render {

std::uint32_t field_mode(SurfaceColour colour) {
    return colour == SurfaceColour::by_speed ? 1u : colour == SurfaceColour::by_pressure ? 2u : 0u;
}

FieldSampler::FieldSampler(cl_rt::Device& device, const device::Grid& grid, const std::string& point_options)
    : device_(device), grid_(grid), wg_(device.work_group_size(64)) {
    std::string opts = point_options;
    if (device.quirks().atomic_min_unreliable) opts += " -DCLSPH_DEPTH_BY_CAS";
    bounds_k_ = device.kernel("render_field.cl", "field_bounds", opts);
    vertex_k_ = device.kernel("render_field.cl", "vertex_field", opts);
}

std::array<double, 2> FieldSampler::bounds(std::uint32_t mode, const SphParams& sp, const device::ParticleStore& store) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::size_t n = store.ranges.owned;
    if (n == 0) return {nan, nan};
    auto out = device_.alloc(2 * sizeof(cl_uint), "field bounds");
    const cl_uint init[2] = {0xffffffffu, 0u};
    device_.write(out, init, 2);
    cl_rt::set_args(bounds_k_, cl_rt::checked_uint(store.ranges.first_owned()), cl_rt::checked_uint(n), cl_uint{mode}, sp,
                    store.velrho, store.id, out);
    device_.launch("render.field_bounds", bounds_k_, n, wg_);
    cl_uint got[2];
    device_.read(out, got, 2);
    if (got[0] == 0xffffffffu && got[1] == 0u) return {nan, nan};  // no fluid owned
    auto value = [](cl_uint u) {
        const cl_uint bits = clsph_unordered_bits(u);
        float f;
        std::memcpy(&f, &bits, 4);
        return static_cast<double>(f);
    };
    return {value(got[0]), value(got[1])};
}

cl_rt::Buffer FieldSampler::vertex_values(std::uint32_t mode, const SphParams& sp, const std::array<double, 2>& range,
                                          const cl_rt::Buffer& points, std::size_t vertices,
                                          const device::ParticleStore& store, const device::CellPipeline& cells) {
    auto out = device_.alloc(std::max<std::size_t>(1, vertices) * sizeof(cl_float), "render vertex field");
    if (vertices == 0) return out;
    const auto& lo = grid_.domain().lo;
    const cl_float2 r{{static_cast<float>(range[0]), static_cast<float>(range[1])}};
    cl_rt::set_args(vertex_k_, cl_rt::checked_uint(vertices), cells.cells(), grid_.params(), sp, cl_uint{mode}, float4_of(lo), r,
                    points, cells.cell_key(), cells.cell_start(), store.pos, store.velrho, store.id, out);
    device_.launch("render.vertex_field", vertex_k_, vertices, wg_);
    return out;
}

std::array<double, 2> field_range(multi::SlabDriver& driver, const device::Grid& grid, const ImageStyle& style) {
    if (std::isfinite(style.range_min) && std::isfinite(style.range_max)) return {style.range_min, style.range_max};
    const std::uint32_t mode = field_mode(style.surface);
    double lo = INFINITY, hi = -INFINITY;
    auto& slabs = driver.slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d) || slabs[d].store->ranges.owned == 0) continue;
        FieldSampler sampler(*slabs[d].device, grid, slabs[d].physics->point_options());
        const auto b = sampler.bounds(mode, driver.params(), *slabs[d].store);
        if (std::isfinite(b[0])) lo = std::min(lo, b[0]);
        if (std::isfinite(b[1])) hi = std::max(hi, b[1]);
    }
    if (Ranks* ranks = driver.ranks()) {  // every rank's particles
        std::vector<double> ends{-lo, hi};
        ranks->max(ends);
        lo = -ends[0];
        hi = ends[1];
    }
    if (!(lo <= hi)) lo = hi = 0;
    if (mode == 1) lo = 0;  // speeds from rest
    // One end given: the other found.
    if (std::isfinite(style.range_min)) lo = style.range_min;
    if (std::isfinite(style.range_max)) hi = style.range_max;
    return {lo, hi};
}

}  // namespace clsph::render
