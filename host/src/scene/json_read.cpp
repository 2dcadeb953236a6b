// The scene document -> Scene (schema: docs/scenes.md). Defaults come from the structs in
// clsph/scene.hpp, so the file format and the C++ API cannot disagree about them.
#include "scene/json_fields.hpp"
#include "scene/json_motion.hpp"
#include "scene/json_open.hpp"
#include "scene/json_scene.hpp"
#include "scene/mesh_obj.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <utility>

namespace clsph::scene {
namespace {

namespace fs = std::filesystem;

PhysicsParams read_physics(const Json& v) {
    Fields f(v, "physics",
             {"dp", "hdp", "kernel", "density", "diffusion", "delta", "rho0", "gamma", "coefsound", "c0", "alpha", "alpha_wall", "viscosity",
              "kinematic_viscosity", "integrator",
              "gravity", "cfl", "density_min", "density_max"});
    PhysicsParams p;
    p.dp = read_number(f.require("dp"), "physics.dp");
    p.hdp = f.number("hdp", p.hdp);
    p.kernel = f.choice("kernel", p.kernel, {{"wendland", KernelType::wendland_c2}, {"cubic", KernelType::cubic_spline}});
    p.density = f.choice("density", p.density,
                         {{"continuity", DensityMode::continuity}, {"summation", DensityMode::summation}});
    p.diffusion = f.choice("diffusion", p.diffusion,
                           {{"none", Diffusion::none},
                            {"molteni", Diffusion::molteni_colagrossi},
                            {"fourtakas", Diffusion::fourtakas}});
    p.delta = f.number("delta", p.delta);
    p.rho0 = f.number("rho0", p.rho0);
    p.gamma = f.number("gamma", p.gamma);
    p.coefsound = f.number("coefsound", p.coefsound);
    p.c0 = f.number("c0", p.c0);
    p.alpha = f.number("alpha", p.alpha);
    p.alpha_wall = f.number("alpha_wall", p.alpha_wall);
    p.viscosity = f.choice("viscosity", p.viscosity,
                           {{"artificial", Viscosity::artificial},
                            {"laminar", Viscosity::laminar},
                            {"laminar+sps", Viscosity::laminar_sps}});
    p.kinematic_viscosity = f.number("kinematic_viscosity", p.kinematic_viscosity);
    p.integrator = f.choice("integrator", p.integrator,
                            {{"leapfrog", Integrator::leapfrog}, {"symplectic", Integrator::symplectic}});
    p.gravity = f.vec3("gravity", p.gravity);
    p.cfl = f.number("cfl", p.cfl);
    p.density_min = f.number("density_min", p.density_min);
    p.density_max = f.number("density_max", p.density_max);
    return p;
}

Domain read_domain(const Json& v) {
    Fields f(v, "domain", {"min", "max", "periodic", "split_axis"});
    Domain d;
    d.min = read_vec3(f.require("min"), "domain.min");
    d.max = read_vec3(f.require("max"), "domain.max");
    if (const Json* p = f.find("periodic")) {
        if (!p->is_array() || p->size() != 3)
            key_error("domain.periodic", "expected 3 booleans (x, y, z), got " + p->dump());
        for (std::size_t k = 0; k < 3; ++k) d.periodic[k] = read_bool((*p)[k], "domain.periodic[" + std::to_string(k) + "]");
    }
    d.split_axis = f.choice("split_axis", -1, {{"auto", -1}, {"x", 0}, {"y", 1}, {"z", 2}});
    return d;
}

FluidBlock read_fluid(const Json& v, const std::string& path) {
    Fields f(v, path, {"min", "max", "velocity", "surface"});
    FluidBlock b;
    b.min = read_vec3(f.require("min"), f.path_of("min"));
    b.max = read_vec3(f.require("max"), f.path_of("max"));
    b.velocity = f.vec3("velocity", b.velocity);
    if (const Json* s = f.find("surface"); s && !s->is_null()) b.surface = read_number(*s, f.path_of("surface"));
    return b;
}

unsigned read_faces(const Json& v, const std::string& path) {
    static const char* names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    const std::string usage = "expected \"all\" or an array of faces such as [\"x-\", \"x+\", \"z-\"]";
    if (v.is_string() && v.get<std::string>() == "all") return all_faces;
    if (!v.is_array()) key_error(path, usage + ", got " + v.dump());
    if (v.empty()) key_error(path, "expected at least one face");
    unsigned faces = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string s = read_string(v[i], path + "[" + std::to_string(i) + "]");
        const auto* it = std::find(names, names + 6, s);
        if (it == names + 6)
            key_error(path + "[" + std::to_string(i) + "]", "unknown face \"" + s + "\" (faces: x-, x+, y-, y+, z-, z+)");
        faces |= 1u << (it - names);
    }
    return faces;
}

// A solid's prescribed motion: {"segments": [...]}, each segment the keys of its type only
// (clsph/scene.hpp, MotionSegment), a "csv" segment the intervals of its file, or {"wave_maker":
// {...}} (scene/json_motion.hpp). Values are checked by Scene::validate. `scene`: the physics and
// run read so far (a wave maker's gravity and end), `base_dir`: what a CSV file is relative to.
Motion read_motion(const Json& v, const std::string& path, const Scene& scene, const std::string& base_dir) {
    Fields f(v, path, {"segments", "wave_maker"});
    Motion m;
    if (const Json* w = f.find("wave_maker")) {
        if (f.find("segments")) key_error(f.path_of("segments"), "give either segments or a wave_maker, not both");
        MotionSegment s;
        m.wave_maker = read_wave_maker(*w, f.path_of("wave_maker"), scene, s);
        m.segments.push_back(s);
        return m;
    }
    using Type = MotionSegment::Type;
    for_each_element(f.require("segments"), f.path_of("segments"), [&](const Json& e, const std::string& at) {
        if (is_csv_segment(e)) {
            for (const auto& s : read_csv_segment(e, at, base_dir)) m.segments.push_back(s);
            return;
        }
        Fields g(e, at, {"type", "start", "end", "velocity", "amplitude", "period", "phase", "axis_point", "axis", "angle",
                         "angular_velocity", "ramp"});
        MotionSegment s;
        if (!g.find("type"))
            key_error(g.path_of("type"), "missing required key (\"linear\", \"sine\", \"sine_rotation\", \"rotation\", \"csv\", "
                                         "\"linear_rotation\", \"ramped_sine\" or \"ramped_sine_rotation\")");
        s.type = g.choice("type", s.type,
                          {{"linear", Type::linear}, {"sine", Type::sine}, {"sine_rotation", Type::sine_rotation},
                           {"rotation", Type::rotation}, {"linear_rotation", Type::linear_rotation}, {"ramped_sine", Type::ramped_sine},
                           {"ramped_sine_rotation", Type::ramped_sine_rotation}});
        const std::string type = read_string(*g.find("type"), g.path_of("type"));
        s.start = read_number(g.require("start"), g.path_of("start"));
        s.end = read_number(g.require("end"), g.path_of("end"));
        // The keys of this type; another type's key is a mistake, not something to ignore.
        std::vector<std::string> own;
        switch (s.type) {
        case Type::linear: own = {"velocity"}; break;
        case Type::sine: own = {"amplitude", "period", "phase"}; break;
        case Type::sine_rotation: own = {"axis_point", "axis", "angle", "period", "phase"}; break;
        case Type::rotation: own = {"axis_point", "axis", "angular_velocity"}; break;
        case Type::linear_rotation: own = {"velocity", "axis_point", "axis", "angular_velocity"}; break;
        case Type::ramped_sine: own = {"amplitude", "period", "ramp"}; break;
        case Type::ramped_sine_rotation: own = {"axis_point", "axis", "angle", "period", "ramp"}; break;
        }
        for (const char* k : {"velocity", "amplitude", "period", "phase", "axis_point", "axis", "angle", "angular_velocity", "ramp"})
            if (g.find(k) && std::find(own.begin(), own.end(), k) == own.end())
                key_error(g.path_of(k), "is not a key of a \"" + type + "\" segment (its keys: start, end, " + [&] {
                    std::string list;
                    for (const auto& o : own) list += (list.empty() ? "" : ", ") + o;
                    return list;
                }() + ")");
        const bool ramped = s.type == Type::ramped_sine || s.type == Type::ramped_sine_rotation;
        if (s.type == Type::linear || s.type == Type::linear_rotation) s.velocity = read_vec3(g.require("velocity"), g.path_of("velocity"));
        if (s.type == Type::sine || s.type == Type::ramped_sine) s.amplitude = read_vec3(g.require("amplitude"), g.path_of("amplitude"));
        if (s.type == Type::sine || s.type == Type::sine_rotation || ramped) {
            s.period = read_number(g.require("period"), g.path_of("period"));
            if (!ramped) s.phase = g.number("phase", s.phase);
        }
        if (ramped) s.ramp = g.number("ramp", s.ramp);
        if (s.type == Type::sine_rotation || s.type == Type::rotation || s.type == Type::linear_rotation ||
            s.type == Type::ramped_sine_rotation) {
            s.axis_point = read_vec3(g.require("axis_point"), g.path_of("axis_point"));
            s.axis = read_vec3(g.require("axis"), g.path_of("axis"));
        }
        if (s.type == Type::sine_rotation || s.type == Type::ramped_sine_rotation) s.angle = read_number(g.require("angle"), g.path_of("angle"));
        if (s.type == Type::rotation || s.type == Type::linear_rotation)
            s.angular_velocity = read_number(g.require("angular_velocity"), g.path_of("angular_velocity"));
        m.segments.push_back(s);
    });
    return m;
}

Motion read_motion_of(Fields& f, const Scene& scene, const std::string& base_dir) {
    const Json* m = f.find("motion");
    return m && !m->is_null() ? read_motion(*m, f.path_of("motion"), scene, base_dir) : Motion{};
}

// A floating body: {"density" | "mass", "centre", "inertia" (9 numbers row-major or 3: the
// diagonal), "name", the free axes, the initial "velocity" and "angular_velocity"}. Values are checked by Scene::validate.
Floating read_floating(const Json& v, const std::string& path) {
    Fields f(v, path, {"density", "mass", "centre", "inertia", "name", "free_translation", "free_rotation", "velocity",
                       "angular_velocity"});
    Floating b;
    b.enabled = true;
    b.name = f.text("name", "");
    b.density = f.number("density", 0.0);
    b.mass = f.number("mass", 0.0);
    if (!f.find("density") && !f.find("mass")) key_error(path, "needs \"density\" (kg/m^3) or \"mass\" (kg)");
    if (f.find("density") && f.find("mass")) key_error(f.path_of("mass"), "give density or mass, not both");
    if (f.find("centre")) b.centre = read_vec3(*f.find("centre"), f.path_of("centre"));
    if (f.find("velocity")) b.velocity = read_vec3(*f.find("velocity"), f.path_of("velocity"));
    if (f.find("angular_velocity")) b.angular_velocity = read_vec3(*f.find("angular_velocity"), f.path_of("angular_velocity"));
    if (const Json* in = f.find("inertia")) {
        const std::string at = f.path_of("inertia");
        if (!in->is_array() || (in->size() != 3 && in->size() != 9))
            key_error(at, "expected 3 numbers (the diagonal) or 9 (a 3x3 matrix, row-major), got " + in->dump());
        std::array<double, 9> m{};
        if (in->size() == 3)
            for (std::size_t k = 0; k < 3; ++k) m[4 * k] = read_number((*in)[k], at + "[" + std::to_string(k) + "]");
        else
            for (std::size_t k = 0; k < 9; ++k) m[k] = read_number((*in)[k], at + "[" + std::to_string(k) + "]");
        b.inertia = m;
    }
    for (auto [key, mask] : {std::pair<const char*, std::array<bool, 3>*>{"free_translation", &b.free_translation},
                             std::pair<const char*, std::array<bool, 3>*>{"free_rotation", &b.free_rotation}})
        if (const Json* m = f.find(key)) {
            if (!m->is_array() || m->size() != 3) key_error(f.path_of(key), "expected 3 booleans (x, y, z), got " + m->dump());
            for (std::size_t k = 0; k < 3; ++k) (*mask)[k] = read_bool((*m)[k], f.path_of(key) + "[" + std::to_string(k) + "]");
        }
    return b;
}

// The range is checked by Scene::validate, for scenes from files and from code alike.
int read_layers(Fields& f, int fallback) { return f.integer("layers", fallback); }

std::string resolve_mesh_path(const Json& v, const std::string& key, const std::string& base_dir) {
    const std::string raw = read_string(v, key);
    if (raw.empty()) key_error(key, "expected the path of a mesh file (.obj, .stl or .ply)");
    fs::path p(raw);
    if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
    std::error_code ec;
    const fs::path abs = fs::absolute(p, ec);
    // Scene::validate checks that it can be read (before any particle is sampled).
    return (ec ? p : abs).lexically_normal().string();
}

MeshObject read_mesh(const Json& v, const std::string& path, const std::string& base_dir, const Scene& scene) {
    Fields f(v, path, {"path", "scale", "translate", "rotate", "fluid", "layers", "motion"});
    MeshObject m;
    m.path = resolve_mesh_path(f.require("path"), f.path_of("path"), base_dir);
    m.scale = f.number("scale", m.scale);
    m.translate = f.vec3("translate", m.translate);
    m.rotate = f.vec3("rotate", m.rotate);
    m.fluid = f.boolean("fluid", m.fluid);
    m.layers = read_layers(f, m.layers);
    m.motion = read_motion_of(f, scene, base_dir);
    return m;
}

void read_boundaries(const Json& v, const std::string& base_dir, Scene& s) {
    Fields f(v, "boundaries", {"walls", "boxes", "meshes", "method", "slip"});
    s.boundary_method = f.choice("method", s.boundary_method, {{"dbc", BoundaryMethod::dbc}, {"mdbc", BoundaryMethod::mdbc}});
    s.wall_slip = f.choice("slip", s.wall_slip, {{"wall", WallSlip::wall}, {"no-slip", WallSlip::no_slip}});
    if (const Json* walls = f.find("walls"))
        for_each_element(*walls, "boundaries.walls", [&](const Json& e, const std::string& path) {
            Fields w(e, path, {"min", "max", "faces", "layers", "motion"});
            BoxWalls b;
            b.min = read_vec3(w.require("min"), w.path_of("min"));
            b.max = read_vec3(w.require("max"), w.path_of("max"));
            if (const Json* faces = w.find("faces")) b.faces = read_faces(*faces, w.path_of("faces"));
            b.layers = read_layers(w, b.layers);
            b.motion = read_motion_of(w, s, base_dir);
            s.walls.push_back(b);
        });
    if (const Json* boxes = f.find("boxes"))
        for_each_element(*boxes, "boundaries.boxes", [&](const Json& e, const std::string& path) {
            Fields w(e, path, {"min", "max", "layers", "motion", "floating"});
            SolidBox b;
            b.min = read_vec3(w.require("min"), w.path_of("min"));
            b.max = read_vec3(w.require("max"), w.path_of("max"));
            b.layers = read_layers(w, b.layers);
            b.motion = read_motion_of(w, s, base_dir);
            if (const Json* fl = w.find("floating"); fl && !fl->is_null()) b.floating = read_floating(*fl, w.path_of("floating"));
            s.solids.push_back(b);
        });
    if (const Json* meshes = f.find("meshes"))
        for_each_element(*meshes, "boundaries.meshes",
                         [&](const Json& e, const std::string& path) { s.meshes.push_back(read_mesh(e, path, base_dir, s)); });
}

// A pressure sensor's face: `normal` (null, as the resolved scene writes it, or absent: a point
// probe) and `size`, which means nothing without a normal, so it is an error there rather than
// silently a point. A height probe is a line and has neither.
void read_sensor_face(Fields& f, Probe& p) {
    const Json* normal = f.find("normal");
    const Json* size = f.find("size");
    if (p.kind == Probe::Kind::height) {
        const char* why = "a height probe has no face (normal and size are a pressure sensor's)";
        if (normal && !normal->is_null()) key_error(f.path_of("normal"), why);
        if (size) key_error(f.path_of("size"), why);
        return;
    }
    if (normal && !normal->is_null()) p.normal = read_vec3(*normal, f.path_of("normal"));
    if (size) {
        if (!p.normal) key_error(f.path_of("size"), "a sensor's size needs its \"normal\" (without one the probe is a point)");
        p.size = read_number(*size, f.path_of("size"));
    }
}

void read_probes(const Json& v, Scene& s) {
    for_each_element(v, "probes", [&](const Json& e, const std::string& path) {
        Fields f(e, path, {"name", "kind", "point", "normal", "size"});
        Probe p;
        p.kind = f.choice("kind", Probe::Kind::pressure, {{"pressure", Probe::Kind::pressure}, {"height", Probe::Kind::height}});
        const bool height = p.kind == Probe::Kind::height;
        p.name = f.text("name", (height ? "height" : "pressure") + std::to_string(s.probes.size()));
        p.point = read_point(f.require("point"), f.path_of("point"), height ? 2 : 3);
        if (height) p.point[2] = 0;  // a height probe is a vertical line at (x, y)
        read_sensor_face(f, p);
        s.probes.push_back(p);
    });
}

RunControl read_run(const Json& v) {
    Fields f(v, "run", {"end_time", "output_every", "probe_every", "fixed_dt", "interaction", "cell_order", "list_buffer"});
    RunControl r;
    r.end_time = f.number("end_time", r.end_time);
    r.output_every = f.number("output_every", r.output_every);
    r.probe_every = f.integer("probe_every", r.probe_every);
    r.fixed_dt = f.number("fixed_dt", r.fixed_dt);
    r.interaction = f.choice("interaction", r.interaction,
                             {{"auto", Interaction::automatic}, {"fine", Interaction::fine}, 
                              {"lanes", Interaction::lanes}, {"coarse", Interaction::coarse},
                              {"clusters", Interaction::clusters}});
    r.cell_order = f.choice("cell_order", r.cell_order,
                            {{"auto", CellOrder::automatic}, {"arrival", CellOrder::arrival}, {"morton", CellOrder::morton}});
    r.list_buffer = f.number("list_buffer", r.list_buffer);
    return r;
}

RenderSettings read_render(const Json& v) {
    Fields f(v, "render", {"method", "camera", "size", "surface_spacing"});
    RenderSettings r;
    r.method = f.choice("method", r.method, {{"surface", RenderMethod::surface}, {"splat", RenderMethod::splat}});
    r.surface_spacing = f.number("surface_spacing", r.surface_spacing);
    if (const Json* c = f.find("camera")) {
        Fields cf(*c, "render.camera", {"eye", "target", "up", "fov"});
        r.has_camera = true;
        r.eye = read_vec3(cf.require("eye"), "render.camera.eye");
        r.target = read_vec3(cf.require("target"), "render.camera.target");
        r.up = cf.vec3("up", r.up);
        r.fov_deg = cf.number("fov", r.fov_deg);
    }
    if (const Json* s = f.find("size")) {
        if (!s->is_array() || s->size() != 2) key_error("render.size", "expected [width, height] in pixels");
        const int w = read_int((*s)[0], "render.size[0]"), h = read_int((*s)[1], "render.size[1]");
        if (w <= 0 || h <= 0) key_error("render.size", "width and height must be positive (got " + std::to_string(w) + " x " + std::to_string(h) + ")");
        r.width = static_cast<std::uint32_t>(w);
        r.height = static_cast<std::uint32_t>(h);
    }
    return r;
}

}  // namespace

std::string scene_name_for(const std::string& path) {
    const std::string stem = fs::path(path).stem().string();
    return stem.empty() ? "scene" : stem;
}

namespace {
// The walls of a scene file that does not choose them (docs/scenes.md, boundaries.method): mDBC
// with wall friction alpha_wall = kMdbcWallFriction unless physics.alpha_wall is given.
void apply_wall_defaults(const Json& doc, Scene& s) {
    auto given = [&](const char* object, const char* key) {
        const auto it = doc.find(object);
        return it != doc.end() && it->is_object() && it->contains(key);
    };
    if (!given("boundaries", "method")) s.boundary_method = BoundaryMethod::mdbc;
    if (s.boundary_method == BoundaryMethod::mdbc && !given("physics", "alpha_wall"))
        s.physics.alpha_wall = kMdbcWallFriction;
}
}  // namespace

Scene scene_from_document(const Json& doc, const DocumentOrigin& origin) {
    Fields top(doc, "", {"name", "physics", "domain", "fluid", "boundaries", "probes", "inlets", "outlets", "run", "render"});
    Scene s;
    s.name = top.text("name", origin.default_name);
    s.physics = read_physics(top.require("physics"));
    s.domain = read_domain(top.require("domain"));
    // The run before the boundaries: a wave maker's motion lasts the run unless it says otherwise.
    if (const Json* r = top.find("run")) s.run = read_run(*r);
    if (const Json* fluid = top.find("fluid"))
        for_each_element(*fluid, "fluid", [&](const Json& e, const std::string& path) { s.fluids.push_back(read_fluid(e, path)); });
    if (const Json* b = top.find("boundaries")) read_boundaries(*b, origin.base_dir, s);
    if (const Json* p = top.find("probes")) read_probes(*p, s);
    read_open_boundaries(top.find("inlets"), top.find("outlets"), origin.base_dir, s);
    if (const Json* r = top.find("render")) s.render = read_render(*r);

    apply_wall_defaults(doc, s);

    const bool fluid_mesh = std::any_of(s.meshes.begin(), s.meshes.end(), [](const MeshObject& m) { return m.fluid; });
    if (s.fluids.empty() && !fluid_mesh)
        key_error("fluid", "the scene has no fluid: give at least one fluid block (or a mesh with \"fluid\": true)");
    s.validate();
    return s;
}

}  // namespace clsph::scene
