// What the Simulation shows of the state now: probe values, the free surface and its image.
#include "simulation/impl.hpp"

#include "probes/gauges.hpp"
#include "render/scene_image.hpp"
#include "surface/extract.hpp"

#include <algorithm>
#include <cmath>

namespace clsph {
namespace {

// The free surface an image draws (render.surface_spacing): sampled as finely as a pixel at the
// camera's target, but no finer than dp / 2 (what clsph surface writes). Triangles smaller than a
// pixel cost time and do not show.
SurfaceOptions image_surface(const Scene& scene, const CameraView& camera) {
    SurfaceOptions o;
    if (scene.render.surface_spacing > 0) {
        o.spacing = scene.render.surface_spacing;
        return o;
    }
    double distance = 0;
    for (std::size_t k = 0; k < 3; ++k) distance += (camera.target[k] - camera.eye[k]) * (camera.target[k] - camera.eye[k]);
    const double pixels_per_unit = 0.5 * camera.height / std::tan(0.5 * camera.fov_deg * 3.14159265358979323846 / 180.0);
    o.spacing = std::max(0.5 * scene.physics.dp, std::sqrt(distance) / pixels_per_unit);
    return o;
}

}  // namespace

std::vector<ProbeSample> Simulation::sample_probes() {
    auto& m = *impl_;
    const auto pp = probes::sample_points(m.scene);
    std::vector<probes::Sums> sums;
    if (const auto* queued = m.ahead.probed(pp.points.size())) {
        sums = *queued;  // computed in the queue after this probe step (the step ahead)
    } else {
        if (!m.ahead.idle())
            throw Error("sample_probes(): steps run ahead of the host (Options::steps_ahead), so inside the step "
                        "callback the probes are available only on probe steps (run.probe_every)");
        sums = cl_rt::guarded("sampling the probes", "", [&] { return m.driver.probe(pp.points); });
    }
    // What each probe measures: probes/gauges.hpp (the same for sums from the step ahead).
    const auto values = probes::values(m.scene, pp, sums);
    std::vector<ProbeSample> out;
    for (std::size_t i = 0; i < m.scene.probes.size(); ++i) out.push_back({m.scene.probes[i].name, m.state.info.time, values[i]});
    return out;
}

TriangleMesh Simulation::surface(const SurfaceOptions& options) {
    auto& m = *impl_;
    m.driver.one_process("free surfaces");
    return cl_rt::guarded("extracting the free surface", "",
                          [&] { return surface::extract_surface(m.driver, m.grid, m.scene, options); });
}

Image Simulation::render(const TriangleMesh& surface, const CameraView& camera, const ImageStyle& style) {
    auto& m = *impl_;
    m.driver.one_process("images");
    return cl_rt::guarded("rendering an image", "", [&] { return render::render_scene(m.driver, m.grid, m.scene, surface, camera, style); });
}

Image Simulation::image(const CameraView& camera, const ImageStyle& style) {
    auto& m = *impl_;
    m.driver.one_process("images");
    if (m.scene.render.method == RenderMethod::surface)
        return cl_rt::guarded("rendering an image", "", [&] {
            // The surface stays where the devices made it; each draws its own part.
            const auto parts = surface::surface_on_devices(m.driver, m.grid, m.scene, image_surface(m.scene, camera));
            return render::render_scene(m.driver, m.grid, m.scene, parts, camera, style, m.frames);
        });
    return cl_rt::guarded("rendering an image by splats", "",
                          [&] { return render::splat_scene(m.driver, m.grid, m.scene, camera, style, m.frames); });
}

}  // namespace clsph
