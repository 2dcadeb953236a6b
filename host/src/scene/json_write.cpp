// Scene -> scene document: every key written, defaults included, so that a run's resolved scene
// (run.json) says exactly what was simulated and reads back to the same Scene.
#include "scene/json_motion.hpp"
#include "scene/json_open.hpp"
#include "scene/json_scene.hpp"

#include <utility>

namespace clsph::scene {
namespace {

Json vec(const Vec3& v) { return Json::array({v[0], v[1], v[2]}); }

const char* kernel_name(KernelType k) { return k == KernelType::cubic_spline ? "cubic" : "wendland"; }
const char* density_name(DensityMode d) { return d == DensityMode::summation ? "summation" : "continuity"; }
const char* diffusion_name(Diffusion d) {
    switch (d) {
        case Diffusion::none: return "none";
        case Diffusion::molteni_colagrossi: return "molteni";
        case Diffusion::fourtakas: break;
    }
    return "fourtakas";
}
const char* axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : a == 2 ? "z" : "auto"; }

Json faces_value(unsigned faces) {
    if ((faces & all_faces) == all_faces) return "all";
    static const char* names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    Json list = Json::array();
    for (int k = 0; k < 6; ++k)
        if (faces & (1u << k)) list.push_back(names[k]);
    return list;
}

// A floating body, written only where there is one.
void put_floating(Json& j, const Floating& f) {
    Json o;
    if (!f.name.empty()) o["name"] = f.name;
    if (f.mass > 0)
        o["mass"] = f.mass;
    else
        o["density"] = f.density;
    if (f.centre) o["centre"] = vec(*f.centre);
    if (f.inertia) {
        Json m = Json::array();
        for (double x : *f.inertia) m.push_back(x);
        o["inertia"] = m;
    }
    for (auto [key, mask] : {std::pair<const char*, const std::array<bool, 3>*>{"free_translation", &f.free_translation},
                             std::pair<const char*, const std::array<bool, 3>*>{"free_rotation", &f.free_rotation}})
        o[key] = Json::array({(*mask)[0], (*mask)[1], (*mask)[2]});
    // The initial velocities only where given: a body at rest writes what it always did, so the
    // scene hash of checkpoints made before these keys existed still matches.
    const Vec3 rest{0, 0, 0};
    if (f.velocity != rest) o["velocity"] = vec(f.velocity);
    if (f.angular_velocity != rest) o["angular_velocity"] = vec(f.angular_velocity);
    j["floating"] = o;
}

// A solid's motion, written only where it has one (a scene without motion writes what it did before).
void put_motion(Json& j, const Motion& m) {
    if (!m.moves()) return;
    if (m.wave_maker) {
        j["motion"] = Json{{"wave_maker", wave_maker_document(*m.wave_maker)}};
        return;
    }
    Json segments = Json::array();
    for (const auto& s : m.segments) {
        Json g;
        using Type = MotionSegment::Type;
        static const char* names[] = {"linear", "sine", "sine_rotation", "rotation", "linear_rotation", "ramped_sine", "ramped_sine_rotation"};
        g["type"] = names[static_cast<int>(s.type)];
        g["start"] = s.start;
        g["end"] = s.end;
        const bool ramped = s.type == Type::ramped_sine || s.type == Type::ramped_sine_rotation;
        if (s.type == Type::linear || s.type == Type::linear_rotation) g["velocity"] = vec(s.velocity);
        if (s.type == Type::sine || s.type == Type::ramped_sine) g["amplitude"] = vec(s.amplitude);
        if (s.type == Type::sine_rotation || s.type == Type::rotation || s.type == Type::linear_rotation || s.type == Type::ramped_sine_rotation) {
            g["axis_point"] = vec(s.axis_point);
            g["axis"] = vec(s.axis);
        }
        if (s.type == Type::sine_rotation || s.type == Type::ramped_sine_rotation) g["angle"] = s.angle;
        if (s.type == Type::rotation || s.type == Type::linear_rotation) g["angular_velocity"] = s.angular_velocity;
        if (s.type == Type::sine || s.type == Type::sine_rotation) {
            g["period"] = s.period;
            g["phase"] = s.phase;
        }
        if (ramped) {
            g["period"] = s.period;
            g["ramp"] = s.ramp;
        }
        segments.push_back(g);
    }
    j["motion"] = Json{{"segments", segments}};
}

Json physics(const PhysicsParams& p) {
    Json j;
    j["dp"] = p.dp;
    j["hdp"] = p.hdp;
    j["kernel"] = kernel_name(p.kernel);
    j["density"] = density_name(p.density);
    j["diffusion"] = diffusion_name(p.diffusion);
    j["delta"] = p.delta;
    j["rho0"] = p.rho0;
    j["gamma"] = p.gamma;
    j["coefsound"] = p.coefsound;
    j["c0"] = p.c0;
    j["alpha"] = p.alpha;
    j["alpha_wall"] = p.alpha_wall;
    j["viscosity"] = p.viscosity == Viscosity::laminar       ? "laminar"
                     : p.viscosity == Viscosity::laminar_sps ? "laminar+sps"
                                                             : "artificial";
    j["kinematic_viscosity"] = p.kinematic_viscosity;
    j["integrator"] = p.integrator == Integrator::symplectic ? "symplectic" : "leapfrog";
    j["gravity"] = vec(p.gravity);
    j["cfl"] = p.cfl;
    j["density_min"] = p.density_min;
    j["density_max"] = p.density_max;
    return j;
}

Json boundaries(const Scene& s) {
    Json walls = Json::array(), boxes = Json::array(), meshes = Json::array();
    for (const auto& w : s.walls) {
        Json j;
        j["min"] = vec(w.min);
        j["max"] = vec(w.max);
        j["faces"] = faces_value(w.faces);
        j["layers"] = w.layers;
        put_motion(j, w.motion);
        walls.push_back(j);
    }
    for (const auto& b : s.solids) {
        Json j;
        j["min"] = vec(b.min);
        j["max"] = vec(b.max);
        j["layers"] = b.layers;
        put_motion(j, b.motion);
        if (b.floating.enabled) put_floating(j, b.floating);
        boxes.push_back(j);
    }
    for (const auto& m : s.meshes) {
        Json j;
        j["path"] = m.path;
        j["scale"] = m.scale;
        j["translate"] = vec(m.translate);
        j["rotate"] = vec(m.rotate);
        j["fluid"] = m.fluid;
        j["layers"] = m.layers;
        put_motion(j, m.motion);
        meshes.push_back(j);
    }
    Json j;
    j["walls"] = walls;
    j["boxes"] = boxes;
    j["meshes"] = meshes;
    j["method"] = s.boundary_method == BoundaryMethod::mdbc ? "mdbc" : "dbc";
    j["slip"] = s.wall_slip == WallSlip::no_slip ? "no-slip" : "wall";
    return j;
}

}  // namespace

Json scene_to_document(const Scene& s) {
    Json doc;
    doc["name"] = s.name;
    doc["physics"] = physics(s.physics);
    Json domain;
    domain["min"] = vec(s.domain.min);
    domain["max"] = vec(s.domain.max);
    domain["periodic"] = Json::array({s.domain.periodic[0], s.domain.periodic[1], s.domain.periodic[2]});
    domain["split_axis"] = axis_name(s.domain.split_axis);
    doc["domain"] = domain;
    Json fluid = Json::array();
    for (const auto& f : s.fluids) {
        Json j;
        j["min"] = vec(f.min);
        j["max"] = vec(f.max);
        j["velocity"] = vec(f.velocity);
        j["surface"] = f.surface ? Json(*f.surface) : Json(nullptr);
        fluid.push_back(j);
    }
    doc["fluid"] = fluid;
    doc["boundaries"] = boundaries(s);
    Json probes = Json::array();
    for (const auto& p : s.probes) {
        Json j;
        j["name"] = p.name;
        const bool height = p.kind == Probe::Kind::height;
        j["kind"] = height ? "height" : "pressure";
        j["point"] = height ? Json::array({p.point[0], p.point[1]}) : vec(p.point);
        if (!height) {
            // The face as given (normalised only where it is used); null: a point probe.
            j["normal"] = p.normal ? vec(*p.normal) : Json(nullptr);
            if (p.normal) j["size"] = p.size;
        }
        probes.push_back(j);
    }
    doc["probes"] = probes;
    write_open_boundaries(s, doc);  // only where there are some (scene/json_open.cpp)
    Json run;
    run["end_time"] = s.run.end_time;
    run["output_every"] = s.run.output_every;
    run["probe_every"] = s.run.probe_every;
    run["fixed_dt"] = s.run.fixed_dt;
    run["interaction"] = interaction_name(s.run.interaction);
    // Only where it is not the default: a scene's hash (checkpoints check it) stays what it was
    // before the key existed.
    if (s.run.cell_order != CellOrder::automatic) run["cell_order"] = cell_order_name(s.run.cell_order);
    if (s.run.list_buffer != 0) run["list_buffer"] = s.run.list_buffer;
    doc["run"] = run;
    Json render;
    render["method"] = s.render.method == RenderMethod::splat ? "splat" : "surface";
    if (s.render.has_camera) {
        Json cam;
        cam["eye"] = vec(s.render.eye);
        cam["target"] = vec(s.render.target);
        cam["up"] = vec(s.render.up);
        cam["fov"] = s.render.fov_deg;
        render["camera"] = cam;
    }
    render["size"] = Json::array({s.render.width, s.render.height});
    if (s.render.surface_spacing != 0) render["surface_spacing"] = s.render.surface_spacing;
    doc["render"] = render;
    return doc;
}

}  // namespace clsph::scene
