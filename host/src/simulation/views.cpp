// What the Simulation shows of the state now: probe values, the free surface and its image.
#include "simulation/impl.hpp"

#include "probes/gauges.hpp"
#include "multi/rigid_bodies.hpp"
#include "render/scene_image.hpp"
#include "scene/motion.hpp"
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

// Where each solid box is now (images draw it there): a prescribed motion's pose at the run's
// time, a floating body's where its particles were last put (centre and orientation); empty when
// no box moves.
std::vector<scene::RigidPose> solid_poses(const Scene& scene, const multi::SlabDriver& driver, double time) {
    const auto* rb = driver.rigid_bodies();
    const bool moving = std::any_of(scene.solids.begin(), scene.solids.end(), [](const SolidBox& b) { return b.motion.moves(); });
    if (!moving && !(rb && rb->size() > 0)) return {};
    std::vector<scene::RigidPose> poses(scene.solids.size());
    for (std::size_t i = 0; i < scene.solids.size(); ++i)
        if (scene.solids[i].motion.moves()) poses[i] = scene::motion_pose(scene.solids[i].motion, time);
    if (rb)
        for (std::size_t b = 0; b < rb->size(); ++b) {
            const auto& body = rb->bodies()[b];
            const auto& s = rb->states()[b];
            scene::RigidPose p;
            p.R = multi::RigidBodies::rotation(s.q_p);
            for (std::size_t k = 0; k < 3; ++k)  // x -> x_p + R (x - centre)
                p.T[k] = s.x_p[k] - (p.R[3 * k] * body.centre[0] + p.R[3 * k + 1] * body.centre[1] + p.R[3 * k + 2] * body.centre[2]);
            if (body.solid < poses.size()) poses[body.solid] = p;
        }
    return poses;
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

std::vector<BodySample> Simulation::bodies() const {
    const auto* rb = impl_->driver.rigid_bodies();
    std::vector<BodySample> out;
    if (!rb) return out;
    for (std::size_t b = 0; b < rb->size(); ++b) {
        const auto& s = rb->states()[b];
        BodySample x;
        x.name = rb->bodies()[b].name;
        x.time = impl_->state.info.time;
        x.position = s.x;
        x.quaternion = s.q;
        x.velocity = s.v;
        x.angular_velocity = s.w;
        x.force = s.force;
        x.torque = s.torque;
        x.mass = rb->bodies()[b].mass;
        out.push_back(x);
    }
    return out;
}

TriangleMesh Simulation::surface(const SurfaceOptions& options) {
    auto& m = *impl_;
    return cl_rt::guarded("extracting the free surface", "",
                          [&] { return surface::extract_surface(m.driver, m.grid, m.scene, options, m.surfaces); });
}

Image Simulation::render(const TriangleMesh& surface, const CameraView& camera, const ImageStyle& style) {
    auto& m = *impl_;
    return cl_rt::guarded("rendering an image", "", [&] { return render::render_scene(m.driver, m.grid, m.scene, surface, camera, style); });
}

Image Simulation::image(const CameraView& camera, const ImageStyle& style) {
    auto& m = *impl_;
    if (m.scene.render.method == RenderMethod::surface)
        return cl_rt::guarded("rendering an image", "", [&] {
            // The surface stays where the devices made it, its counts too; each device draws its own
            // part. Only then are the counts read: where one outgrew its capacity, surface and
            // image are made again (the capacities kept for the next frames).
            const auto poses = solid_poses(m.scene, m.driver, m.state.info.time);
            for (int attempt = 0;; ++attempt) {
                surface::surface_on_devices(m.driver, m.grid, m.scene, image_surface(m.scene, camera), m.surfaces);
                Image img = render::render_scene(m.driver, m.grid, m.scene, m.surfaces, camera, style, m.frames, poses);
                if (surface::settle_everywhere(m.driver, m.surfaces)) return img;
                if (attempt == 3) throw Error("image: the surface's buffers did not settle after four attempts (a bug: please report it)");
            }
        });
    return cl_rt::guarded("rendering an image by splats", "",
                          [&] { return render::splat_scene(m.driver, m.grid, m.scene, camera, style, m.frames, solid_poses(m.scene, m.driver, m.state.info.time)); });
}

}  // namespace clsph
