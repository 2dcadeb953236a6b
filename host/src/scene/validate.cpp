// Scene::validate: every check of a scene's values, for scenes read from JSON (the reader checks
// only syntax and types, then calls this) and for scenes built in C++, so both paths accept the
// same scenes and say the same thing about the rest. Cheap: O(blocks log blocks), no particle.
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "scene/floating.hpp"
#include "scene/fluid_overlaps.hpp"
#include "scene/lattice.hpp"
#include "scene/mesh_formats.hpp"
#include "scene/open_boundaries.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <set>
#include <sstream>

namespace clsph {
namespace {

std::string vec(const Vec3& v) {
    std::ostringstream o;
    o << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
    return o.str();
}

std::string num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

void require(bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw SceneError(key + ": " + what);
}

// The same, with the key and the message made only on failure (checks run once per block, and a
// scene may have 100,000 blocks).
template <class Key, class What>
void require_lazy(bool ok, Key&& key, What&& what) {
    if (!ok) throw SceneError(key() + ": " + what());
}

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

void require_finite(const Vec3& v, const std::string& key) { require(finite(v), key, "expected 3 finite numbers, got " + vec(v)); }

void require_layers(int layers, int least, const std::string& key) {
    require(layers >= least && layers <= 16, key,
            "must be " + std::to_string(least) + " to 16 (got " + std::to_string(layers) + ")");
}

const char* face_name(int bit) {
    static const char* names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    return names[bit];
}

bool valid_probe_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
    return name != "." && name != "..";
}

// A pressure sensor's face. A normal of any length is accepted and normalised where it is used
// (a direction is what it says); zero has no direction, so it is an error, as is a size that is
// not a positive length.
void check_sensor_face(const Probe& pr, const std::string& key) {
    require(pr.kind == Probe::Kind::pressure, key + ".normal",
            "a height probe has no face (normal and size are a pressure sensor's)");
    const Vec3& n = *pr.normal;
    require_finite(n, key + ".normal");
    require(n[0] != 0 || n[1] != 0 || n[2] != 0, key + ".normal",
            "must not be the zero vector (it points from the wall into the fluid)");
    require(std::isfinite(pr.size) && pr.size > 0, key + ".size",
            "must be the sensor's diameter, a finite length > 0 m (got " + num(pr.size) + ")");
}

// Lattice points of a fluid block (0 when dp is larger than the block, or the block lies between
// lattice points), as a double so that absurd blocks do not overflow.
double lattice_points(const FluidBlock& f, double dp) {
    double n = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double first = std::ceil(f.min[k] / dp - 1e-9), last = std::floor(f.max[k] / dp + 1e-9);
        n *= std::max(0.0, last - first + 1.0);
    }
    return n;
}

// Where a box's boundary particles lie: walls grow outward by layers - 1 spacings on each
// selected face; everything else lies within [min, max].
void particle_extent(const BoxWalls& w, double dp, Vec3& lo, Vec3& hi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = w.min[a] - ((w.faces >> (2 * a)) & 1u ? (w.layers - 1) * dp : 0.0);
        hi[a] = w.max[a] + ((w.faces >> (2 * a + 1)) & 1u ? (w.layers - 1) * dp : 0.0);
    }
}

// A solid's motion (clsph/scene.hpp, MotionSegment): finite numbers, segments of positive length
// in increasing order without overlap, a positive period, a non-zero axis.
void check_motion(const Motion& m, const std::string& solid) {
    using Type = MotionSegment::Type;
    for (std::size_t i = 0; i < m.segments.size(); ++i) {
        const auto& s = m.segments[i];
        const std::string key = solid + ".motion.segments[" + std::to_string(i) + "]";
        require(std::isfinite(s.start), key + ".start", "must be a finite time (s), got " + num(s.start));
        require(std::isfinite(s.end), key + ".end", "must be a finite time (s), got " + num(s.end));
        require(s.end > s.start, key + ".end", "must be after start (" + num(s.end) + " <= " + num(s.start) + ")");
        if (i > 0)
            require(s.start >= m.segments[i - 1].end, key + ".start",
                    "overlaps the segment before it, which ends at " + num(m.segments[i - 1].end) +
                        " s (segments are in increasing time, without overlap)");
        const bool ramped = s.type == Type::ramped_sine || s.type == Type::ramped_sine_rotation;
        if (s.type == Type::linear || s.type == Type::linear_rotation) require_finite(s.velocity, key + ".velocity");
        if (s.type == Type::sine || s.type == Type::ramped_sine) require_finite(s.amplitude, key + ".amplitude");
        if (ramped) {
            require(std::isfinite(s.period) && s.period > 0, key + ".period", "must be a finite time > 0 s, got " + num(s.period));
            require(std::isfinite(s.ramp) && s.ramp >= 0, key + ".ramp", "must be a finite time >= 0 s, got " + num(s.ramp));
        }
        if (s.type == Type::sine || s.type == Type::sine_rotation) {
            require(std::isfinite(s.period) && s.period > 0, key + ".period", "must be a finite time > 0 s, got " + num(s.period));
            require(std::isfinite(s.phase), key + ".phase", "must be a finite angle (rad), got " + num(s.phase));
        }
        if (s.type == Type::sine_rotation || s.type == Type::rotation || s.type == Type::linear_rotation ||
            s.type == Type::ramped_sine_rotation) {
            require_finite(s.axis_point, key + ".axis_point");
            require_finite(s.axis, key + ".axis");
            require(s.axis[0] != 0 || s.axis[1] != 0 || s.axis[2] != 0, key + ".axis", "must not be the zero vector");
        }
        if (s.type == Type::sine_rotation || s.type == Type::ramped_sine_rotation) require(std::isfinite(s.angle), key + ".angle", "must be a finite angle (rad), got " + num(s.angle));
        if (s.type == Type::rotation || s.type == Type::linear_rotation)
            require(std::isfinite(s.angular_velocity), key + ".angular_velocity",
                    "must be a finite angular velocity (rad/s), got " + num(s.angular_velocity));
    }
}

}  // namespace

bool Scene::has_motion() const {
    for (const auto& w : walls)
        if (w.motion.moves()) return true;
    for (const auto& b : solids)
        if (b.motion.moves()) return true;
    for (const auto& m : meshes)
        if (m.motion.moves()) return true;
    return false;
}

void Scene::validate() const {
    const auto& p = physics;
    auto finite_pos = [](double v) { return std::isfinite(v) && v > 0; };
    require(finite_pos(p.dp), "physics.dp", "must be a positive number (got " + std::to_string(p.dp) + ")");
    require(finite_pos(p.hdp), "physics.hdp", "must be positive");
    require(p.support() > p.dp, "physics.hdp",
            "the kernel support 2 hdp dp = " + num(p.support()) + " m does not reach beyond dp = " + num(p.dp) +
                " m, so no particle would have a neighbour (hdp must be more than 0.5; 2 is the default)");
    require(finite_pos(p.rho0), "physics.rho0", "must be positive");
    require(p.gamma == 7.0, "physics.gamma", "only 7 is supported (the kernels expand the power)");
    require(finite_pos(p.coefsound), "physics.coefsound", "must be a positive number (c0 = coefsound sqrt(g H))");
    require(std::isfinite(p.c0) && p.c0 >= 0, "physics.c0", "must be >= 0 (0: derived from coefsound)");
    require(p.cfl > 0 && p.cfl <= 1.0, "physics.cfl", "must be in (0, 1]");
    require(p.alpha >= 0 && std::isfinite(p.alpha), "physics.alpha", "must be >= 0");
    require(p.alpha_wall >= 0 && std::isfinite(p.alpha_wall), "physics.alpha_wall", "must be >= 0");
    require(p.kinematic_viscosity >= 0 && std::isfinite(p.kinematic_viscosity), "physics.kinematic_viscosity",
            "must be a finite number >= 0 (m^2/s; water: 1e-6)");
    require(p.delta >= 0 && std::isfinite(p.delta), "physics.delta", "must be >= 0");
    require_finite(p.gravity, "physics.gravity");
    require(p.density_min < 1.0 && p.density_max > 1.0 && p.density_min > 0 && std::isfinite(p.density_max),
            "physics.density_min", "the density band must contain 1 (as a fraction of rho0)");

    require_finite(domain.min, "domain.min");
    require_finite(domain.max, "domain.max");
    for (int k = 0; k < 3; ++k)
        require(domain.max[k] > domain.min[k], "domain.max", "must be greater than domain.min on every axis");
    require(domain.split_axis >= -1 && domain.split_axis <= 2, "domain.split_axis", "must be -1 (auto), 0, 1 or 2");

    require(std::isfinite(run.end_time) && run.end_time >= 0, "run.end_time", "must be a finite time >= 0 s");
    require(std::isfinite(run.output_every) && run.output_every > 0, "run.output_every", "must be a finite time > 0 s");
    require(run.probe_every >= 1, "run.probe_every", "must be >= 1");
    require(std::isfinite(run.fixed_dt) && run.fixed_dt >= 0, "run.fixed_dt",
            "must be a finite time >= 0 s (0: the adaptive CFL step)");
    require(std::isfinite(run.list_buffer) && run.list_buffer >= 0 && run.list_buffer <= 1, "run.list_buffer",
            "must be a fraction of the kernel support from 0 (sorted every step) to 1");

    require(render.method == RenderMethod::surface || render.method == RenderMethod::splat, "render.method",
            "must be \"surface\" or \"splat\"");
    require(render.width > 0 && render.height > 0 && render.width <= 16384 && render.height <= 16384, "render.size",
            "width and height must be 1 to 16384 pixels");
    if (render.has_camera) {
        require_finite(render.eye, "render.camera.eye");
        require_finite(render.target, "render.camera.target");
        require_finite(render.up, "render.camera.up");
        Vec3 view{render.target[0] - render.eye[0], render.target[1] - render.eye[1], render.target[2] - render.eye[2]};
        const double vl = std::sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
        require(vl > 0, "render.camera.eye", "is at the target: the camera looks nowhere");
        const double ul = std::sqrt(render.up[0] * render.up[0] + render.up[1] * render.up[1] + render.up[2] * render.up[2]);
        require(ul > 0, "render.camera.up", "must not be the zero vector");
        const Vec3 c{view[1] * render.up[2] - view[2] * render.up[1], view[2] * render.up[0] - view[0] * render.up[2],
                     view[0] * render.up[1] - view[1] * render.up[0]};
        require(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) > 1e-6 * vl * ul, "render.camera.up",
                "must not point along the view direction (eye to target)");
        require(std::isfinite(render.fov_deg) && render.fov_deg > 0 && render.fov_deg < 180, "render.camera.fov",
                "must be an angle in (0, 180) degrees");
    }
    require(std::isfinite(render.surface_spacing) && render.surface_spacing >= 0, "render.surface_spacing",
            "must be a length in metres, or 0 for the automatic spacing (as fine as a pixel, no finer than dp / 2)");

    const double tol = 1e-9 * p.dp;
    auto inside = [&](const Vec3& a) {
        for (int k = 0; k < 3; ++k)
            if (!(a[k] >= domain.min[k] - tol && a[k] <= domain.max[k] + tol)) return false;
        return true;
    };
    for (std::size_t i = 0; i < fluids.size(); ++i) {
        const auto& f = fluids[i];
        const auto key = [i] { return "fluid[" + std::to_string(i) + "]"; };
        const auto sub = [&](const char* k) { return [&, k] { return key() + k; }; };
        require_lazy(finite(f.min), sub(".min"), [&] { return "expected 3 finite numbers, got " + vec(f.min); });
        require_lazy(finite(f.max), sub(".max"), [&] { return "expected 3 finite numbers, got " + vec(f.max); });
        require_lazy(finite(f.velocity), sub(".velocity"), [&] { return "expected 3 finite numbers, got " + vec(f.velocity); });
        if (f.surface) require_lazy(std::isfinite(*f.surface), sub(".surface"), [] { return std::string("must be a finite height (m)"); });
        for (int k = 0; k < 3; ++k)
            require_lazy(f.max[k] > f.min[k], sub(".max"), [] { return std::string("must be greater than min on every axis"); });
        require_lazy(inside(f.min) && inside(f.max), key, [&] {
            return "block " + vec(f.min) + " - " + vec(f.max) + " is not inside the domain " + vec(domain.min) + " - " +
                   vec(domain.max);
        });
        require_lazy(lattice_points(f, p.dp) >= 1, key, [&] {
            return "holds no fluid particle: no point of the dp lattice (physics.dp = " + num(p.dp) + " m) lies in the block " +
                   vec(f.min) + " - " + vec(f.max);
        });
    }
    scene::check_fluid_overlaps(fluids);

    require(wall_slip == WallSlip::wall || boundary_method == BoundaryMethod::mdbc, "boundaries.slip",
            "\"no-slip\" needs mDBC walls (boundaries.method \"mdbc\"): the mirrored velocity is interpolated at the "
            "ghost nodes, which \"dbc\" walls do not have");
    for (std::size_t i = 0; i < walls.size(); ++i) {
        const auto& w = walls[i];
        const std::string key = "boundaries.walls[" + std::to_string(i) + "]";
        require_finite(w.min, key + ".min");
        require_finite(w.max, key + ".max");
        require_layers(w.layers, 1, key + ".layers");
        for (int k = 0; k < 3; ++k) require(w.max[k] > w.min[k], key + ".max", "must be greater than min");
        require(w.faces != 0 && w.faces <= all_faces, key + ".faces", "expected at least one face");
        check_motion(w.motion, key);
        for (int bit = 0; bit < 6; ++bit)
            require(!((w.faces >> bit) & 1u) || !domain.periodic[static_cast<std::size_t>(bit / 2)], key + ".faces",
                    std::string("face ") + face_name(bit) + " is on the periodic axis " + "xyz"[bit / 2] +
                        " (particles leaving one end come back at the other: a periodic axis has no walls)");
        Vec3 lo, hi;
        particle_extent(w, p.dp, lo, hi);
        require(inside(lo) && inside(hi), key,
                "its particles span " + vec(lo) + " - " + vec(hi) + ", outside the domain " + vec(domain.min) + " - " +
                    vec(domain.max) + " (particles outside the domain are removed)");
    }
    for (std::size_t i = 0; i < solids.size(); ++i) {
        const auto& b = solids[i];
        const std::string key = "boundaries.boxes[" + std::to_string(i) + "]";
        require_finite(b.min, key + ".min");
        require_finite(b.max, key + ".max");
        require_layers(b.layers, 0, key + ".layers");
        for (int k = 0; k < 3; ++k) require(b.max[k] > b.min[k], key + ".max", "must be greater than min");
        check_motion(b.motion, key);
        require(inside(b.min) && inside(b.max), key,
                "box " + vec(b.min) + " - " + vec(b.max) + " is not inside the domain " + vec(domain.min) + " - " +
                    vec(domain.max) + " (particles outside the domain are removed)");
    }
    // Fluid placed inside a solid box would be trapped inside its shell of boundary particles.
    if (!solids.empty())
        for (std::size_t i = 0; i < fluids.size(); ++i)
            for (std::size_t j = 0; j < solids.size(); ++j) {
                const FluidBlock& f = fluids[i];
                const SolidBox& b = solids[j];
                if (b.floating.enabled && b.layers == 0) continue;  // filled: the fluid there is left out
                bool overlap = true;
                for (int k = 0; k < 3; ++k) overlap = overlap && f.min[k] < b.max[k] - tol && b.min[k] < f.max[k] - tol;
                require_lazy(!overlap, [i] { return "fluid[" + std::to_string(i) + "]"; }, [&] {
                    return "overlaps the solid boundaries.boxes[" + std::to_string(j) + "] " + vec(b.min) + " - " +
                           vec(b.max) + " (fluid cannot start inside a solid)";
                });
            }
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const auto& m = meshes[i];
        const std::string key = "boundaries.meshes[" + std::to_string(i) + "]";
        require(!m.path.empty(), key + ".path", "expected the path of a mesh file (.obj, .stl or .ply)");
        if (const std::string why = scene::mesh_path_problem(m.path); !why.empty())
            throw SceneError(key + ".path: cannot read \"" + m.path + "\": " + why);
        require(std::isfinite(m.scale) && m.scale > 0, key + ".scale", "must be positive");
        require_finite(m.translate, key + ".translate");
        require_finite(m.rotate, key + ".rotate");
        require_layers(m.layers, 1, key + ".layers");
        require(!(m.fluid && m.motion.moves()), key + ".motion", "a fluid mesh cannot move (only solids have a motion)");
        check_motion(m.motion, key);
    }

    std::set<std::string> names;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const auto& pr = probes[i];
        const std::string key = "probes[" + std::to_string(i) + "]";
        // Probe names become file names (one CSV per probe).
        require(valid_probe_name(pr.name), key + ".name",
                "\"" + pr.name + "\" is not a usable name (letters, digits, _ - . only, at most 64)");
        require(names.insert(pr.name).second, key + ".name", "another probe is already named \"" + pr.name + "\"");
        require_finite(pr.point, key + ".point");
        require(inside(pr.kind == Probe::Kind::height ? Vec3{pr.point[0], pr.point[1], domain.min[2]} : pr.point),
                key + ".point", "is outside the domain");
        if (pr.normal) check_sensor_face(pr, key);
    }

    // Estimated particle counts before sampling, so an absurd dp fails fast and clearly.
    double fluid = 0.0, boundary = 0.0;
    for (const auto& f : fluids) fluid += lattice_points(f, p.dp);
    for (const auto& w : walls) {
        Vec3 lo, hi;
        particle_extent(w, p.dp, lo, hi);
        double whole = 1.0, inner = 1.0;
        for (int k = 0; k < 3; ++k) whole *= (hi[k] - lo[k]) / p.dp + 1.0, inner *= (w.max[k] - w.min[k]) / p.dp;
        boundary += std::max(0.0, whole - inner);
    }
    for (const auto& b : solids) {
        double n = 1.0;
        for (int k = 0; k < 3; ++k) n *= (b.max[k] - b.min[k]) / p.dp + 1.0;
        boundary += n;
    }
    // Ids are 31 bits (kernels/shared.h): at most 2^31 - 1 particles.
    constexpr double id_limit = 2147483647.0;
    if (!(fluid < id_limit)) {
        std::ostringstream o;  // a plain whole number, however large (an integer cast would overflow)
        o << std::fixed << std::setprecision(0) << "gives about " << fluid << " fluid particles; clsph ids allow at most 2^31 - 1 (2.1e9)";
        throw SceneError("physics.dp: " + o.str());
    }
    if (!(fluid + boundary < id_limit)) {
        std::ostringstream o;
        o << std::fixed << std::setprecision(0) << "gives about " << boundary
          << " boundary particles (walls and boxes) beside the fluid; clsph ids allow at most 2^31 - 1 (2.1e9) in all";
        throw SceneError("physics.dp: " + o.str());
    }
    scene::check_floating(*this);
    scene::check_open_boundaries(*this);
    (void)sound_speed();
}

}  // namespace clsph
