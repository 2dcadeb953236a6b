// An image of a simulation by splats (render.method "splat"): every device splats the fluid
// particles it owns (no ghosts: each particle is drawn once), the first device merges the others'
// images into its own, renders the solid boxes (Renderer, as the surface method does) and shades
// the water over them and draws the walls' outlines with the depth test, all in its memory: only
// the other devices' splats and the finished picture cross to the host.
#include "render/scene_image.hpp"
#include "render/field.hpp"
#include "render/frame_cache.hpp"
#include "render/rank_images.hpp"
#include "render/splat.hpp"

#include "clsph/error.hpp"

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
                  const ImageStyle& style, FrameCache& cache, const std::vector<scene::RigidPose>& poses) {
    auto& slabs = driver.slabs();
    const double radius = kSplatRadius * scene.physics.dp;
    SplatField field;
    field.mode = field_mode(style.surface);
    if (field.mode) {
        field.range = field_range(driver, grid, style);
        field.sp = driver.params();
    }
    // The first device here shades: its splats stay where they are drawn, the others' are read
    // back and merged into them there (only images cross devices).
    // Across ranks the others send their slabs' splats to rank 0, which merges them after its own
    // (their slabs come after its slabs), as one process merges its devices'.
    Ranks* ranks = driver.ranks();
    const bool root = !ranks || ranks->rank() == 0;
    SlabImages<SplatImage> sent;
    Splatter* water = nullptr;
    cl_rt::Device* shading = nullptr;
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;
        auto& s = slabs[d];
        if ((water || !root) && s.store->ranges.owned == 0) continue;
        Splatter& splatter = cache.splatter(*s.device, grid);
        splatter.splat(camera, *s.store, s.store->ranges.first_owned(), s.store->ranges.owned, radius, field);
        if (!root) {
            sent.emplace_back(d, splatter.read());
        } else if (!water) {
            water = &splatter;
            shading = s.device;
        } else {
            water->merge(splatter.read());
        }
    }
    if (ranks) {
        const auto received = gather_to_rank0(*ranks, sent);
        if (!root) {
            Image none;
            if (field.mode) none.range = field.range;
            return none;
        }
        for (const auto& [d, im] : received) water->merge(im);
    }
    if (!water) throw Error("splat: no device holds the run here");
    RenderTarget solids;
    UploadedLayer moved;
    if (!scene.solids.empty())
        solids = cache.renderer(*shading).render(camera, {solids_layer(cache, *shading, scene, poses, moved)});
    const RenderTarget im = cache.shader(*shading).shade(camera, *water, solids.depth ? &solids : nullptr, environment_of(scene, camera));
    // The shading coloured every pixel (the sky and the ground where nothing else is).
    Image out = cache.finisher(*shading).finish(im, line_pixels(camera, wall_lines(scene.walls)), {70, 70, 70}, {0, 0, 0}, true);
    if (field.mode) out.range = field.range;
    return out;
}

}  // namespace clsph::render
