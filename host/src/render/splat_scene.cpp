// An image of a simulation by splats (render.method "splat"): every device splats the fluid
// particles it owns (no ghosts: each particle is drawn once), the host composites the images, the
// first device renders the solid boxes (Renderer, as the surface method does) and shades the water
// over them, and the walls' outlines are drawn last with the depth test.
#include "render/scene_image.hpp"
#include "render/field.hpp"
#include "render/splat.hpp"

#include <algorithm>
#include <cmath>

namespace clsph::render {
namespace {

Environment environment_of(const Scene& scene, const CameraView& camera) {
    Environment env;
    const auto& g = scene.physics.gravity;
    const double gl = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    env.up = gl > 0 ? Vec3{-g[0] / gl, -g[1] / gl, -g[2] / gl} : camera.up;
    const double ul = std::sqrt(env.up[0] * env.up[0] + env.up[1] * env.up[1] + env.up[2] * env.up[2]);
    for (auto& c : env.up) c /= ul;
    // The ground: the domain's lowest corner along up. Its checker and the water's colour scale with
    // the domain and the fluid, so a tank of 0.5 m and a lake of 50 m look alike.
    double ground = 1e300, extent = 0;
    for (int corner = 0; corner < 8; ++corner) {
        double h = 0;
        for (std::size_t k = 0; k < 3; ++k) h += ((corner >> k) & 1 ? scene.domain.max[k] : scene.domain.min[k]) * env.up[k];
        ground = std::min(ground, h);
    }
    for (std::size_t k = 0; k < 3; ++k) extent = std::max(extent, scene.domain.max[k] - scene.domain.min[k]);
    double fluid = 0;
    for (const auto& f : scene.fluids)
        for (std::size_t k = 0; k < 3; ++k) fluid = std::max(fluid, f.max[k] - f.min[k]);
    if (!(fluid > 0)) fluid = extent;
    env.ground = ground;
    env.tile = extent / 12;
    for (std::size_t c = 0; c < 3; ++c) env.absorb[c] = std::array<double, 3>{3.5, 1.1, 0.55}[c] / fluid;
    env.radius = kSplatRadius * scene.physics.dp;
    return env;
}

}  // namespace

Image splat_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const CameraView& camera,
                  const ImageStyle& style) {
    auto& slabs = driver.slabs();
    const double radius = kSplatRadius * scene.physics.dp;
    SplatField field;
    field.mode = field_mode(style.surface);
    if (field.mode) {
        field.range = field_range(driver, grid, style);
        field.sp = driver.params();
    }
    std::vector<SplatImage> splats;
    cl_rt::Device* shading = nullptr;
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;
        auto& s = slabs[d];
        if (!shading) shading = s.device;
        if (s.store->ranges.owned == 0 && !splats.empty()) continue;
        Splatter splatter(*s.device, grid);
        splats.push_back(splatter.draw(camera, *s.store, s.store->ranges.first_owned(), s.store->ranges.owned, radius, field));
    }
    const SplatImage water = composite(splats);
    DepthImage solids;
    const TriangleMesh boxes = box_mesh(scene.solids);
    if (!boxes.triangles.empty()) {
        Layer layer{&boxes, {}, {0.62f, 0.60f, 0.58f}};
        for (std::uint32_t t = 0; t < boxes.triangles.size(); ++t) layer.triangles.push_back(t);
        solids = Renderer(*shading).draw(camera, {layer});
    }
    SplatShader shader(*shading);
    DepthImage im = shader.shade(camera, water, solids, environment_of(scene, camera));
    draw_lines(im, camera, wall_lines(scene.walls), {70, 70, 70});
    Image out;
    if (field.mode) out.range = field.range;
    out.width = im.width;
    out.height = im.height;
    out.rgb.resize(std::size_t{3} * im.width * im.height);
    for (std::size_t p = 0; p < im.colour.size(); ++p)
        for (std::size_t c = 0; c < 3; ++c) out.rgb[3 * p + c] = static_cast<std::uint8_t>((im.colour[p] >> (8 * c)) & 0xffu);
    return out;
}

}  // namespace clsph::render
