#include "scene/floating.hpp"

#include "clsph/error.hpp"
#include "scene/lattice.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <utility>

namespace clsph::scene {
namespace {

std::string num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

void require(bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw SceneError(key + ": " + what);
}

}  // namespace

std::vector<FloatingBody> floating_bodies(const Scene& scene) {
    std::vector<FloatingBody> out;
    const double dp = scene.physics.dp;
    for (std::size_t i = 0; i < scene.solids.size(); ++i) {
        const SolidBox& b = scene.solids[i];
        if (!b.floating.enabled) continue;
        FloatingBody f;
        f.key = "boundaries.boxes[" + std::to_string(i) + "]";
        f.name = b.floating.name.empty() ? "box" + std::to_string(i) : b.floating.name;
        f.solid = i;
        f.free_translation = b.floating.free_translation;
        f.free_rotation = b.floating.free_rotation;
        f.velocity = b.floating.velocity;
        f.angular_velocity = b.floating.angular_velocity;
        std::vector<Vec3> pts;
        sample_solid(b, dp, pts);
        f.count = pts.size();
        // The box's volume: its particles stand for the extent plus dp/2 on every side.
        double volume = 1.0;
        for (int k = 0; k < 3; ++k) volume *= b.max[k] - b.min[k] + dp;
        f.mass = b.floating.mass > 0 ? b.floating.mass : b.floating.density * volume;
        const double m = f.mass / static_cast<double>(std::max<std::size_t>(1, pts.size()));
        Vec3 c{0, 0, 0};
        for (const auto& x : pts)
            for (int k = 0; k < 3; ++k) c[k] += x[k] / static_cast<double>(pts.size());
        f.centre = b.floating.centre ? *b.floating.centre : c;
        if (b.floating.inertia) {
            f.inertia = *b.floating.inertia;
        } else {
            // I = sum m (|r|^2 1 - r r^T) about the centre.
            for (const auto& x : pts) {
                const Vec3 r{x[0] - f.centre[0], x[1] - f.centre[1], x[2] - f.centre[2]};
                const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
                for (int a = 0; a < 3; ++a)
                    for (int e = 0; e < 3; ++e) f.inertia[3 * a + e] += m * ((a == e ? r2 : 0.0) - r[a] * r[e]);
            }
        }
        out.push_back(f);
    }
    return out;
}

std::vector<std::int32_t> floating_body_of(const Scene& scene, const Particles& p) {
    const double dp = scene.physics.dp;
    std::vector<std::pair<std::uint64_t, std::int32_t>> owner;  // lattice key, body (first wins)
    std::int32_t next = 0;
    for (const auto& b : scene.solids) {
        if (!b.floating.enabled) continue;
        std::vector<Vec3> pts;
        sample_solid(b, dp, pts);
        for (const auto& x : pts) owner.emplace_back(lattice_key(x, dp), next);
        ++next;
    }
    std::stable_sort(owner.begin(), owner.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::int32_t> out(p.size(), -1);
    if (owner.empty()) return out;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary) continue;
        const std::uint64_t k = lattice_key(p.position[i], dp);
        const auto it = std::lower_bound(owner.begin(), owner.end(), k, [](const auto& e, std::uint64_t v) { return e.first < v; });
        if (it != owner.end() && it->first == k) out[i] = it->second;
    }
    return out;
}

void check_floating(const Scene& scene) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < scene.solids.size(); ++i) {
        const Floating& f = scene.solids[i].floating;
        if (!f.enabled) continue;
        const std::string key = "boundaries.boxes[" + std::to_string(i) + "].floating";
        require(!scene.solids[i].motion.moves(), key,
                "a floating solid cannot have a prescribed motion too (the fluid moves it; remove \"motion\" or \"floating\")");
        if (f.mass != 0)
            require(std::isfinite(f.mass) && f.mass > 0, key + ".mass", "must be a finite mass > 0 kg, got " + num(f.mass));
        else
            require(std::isfinite(f.density) && f.density > 0, key + ".density",
                    "must be a finite density > 0 kg/m^3, got " + num(f.density));
        if (f.centre)
            for (int k = 0; k < 3; ++k)
                require(std::isfinite((*f.centre)[k]), key + ".centre", "expected 3 finite numbers");
        // The initial velocities: finite, and none along an axis the body may not move or turn on
        // (the integrator holds those components at 0).
        auto initial = [&](const char* what, const Vec3& v, const std::array<bool, 3>& free, const char* mask) {
            for (int k = 0; k < 3; ++k) {
                require(std::isfinite(v[k]), key + "." + what, "expected 3 finite numbers");
                require(v[k] == 0 || free[k], key + "." + what,
                        "has " + num(v[k]) + " along " + "xyz"[k] + ", which " + mask + " holds fixed");
            }
        };
        initial("velocity", f.velocity, f.free_translation, "free_translation");
        initial("angular_velocity", f.angular_velocity, f.free_rotation, "free_rotation");
        if (f.inertia) {
            const auto& m = *f.inertia;
            for (double x : m) require(std::isfinite(x), key + ".inertia", "expected finite numbers (kg m^2)");
            for (int a = 0; a < 3; ++a)
                for (int e = 0; e < a; ++e)
                    require(m[3 * a + e] == m[3 * e + a], key + ".inertia", "must be symmetric");
            // Positive definite (Sylvester): the leading minors.
            const double d1 = m[0], d2 = m[0] * m[4] - m[1] * m[3];
            const double d3 = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                              m[2] * (m[3] * m[7] - m[4] * m[6]);
            require(d1 > 0 && d2 > 0 && d3 > 0, key + ".inertia", "must be positive definite (a body's inertia about its centre)");
        }
        const std::string name = f.name.empty() ? "box" + std::to_string(i) : f.name;
        bool usable = !name.empty() && name.size() <= 64;
        for (char c : name) usable = usable && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
        require(usable, key + ".name", "\"" + name + "\" is not a usable name (letters, digits, _ - . only, at most 64: body_NAME.csv)");
        require(std::find(names.begin(), names.end(), name) == names.end(), key + ".name",
                "another floating body is already named \"" + name + "\"");
        names.push_back(name);
    }
    if (!scene.has_floating()) return;
    // A lattice point a floating box shares with a wall or another box is the first solid's particle,
    // and would move with the body: refused (meshes are not checked here).
    const double dp = scene.physics.dp;
    std::vector<std::uint64_t> others;
    std::vector<Vec3> pts;
    for (const auto& w : scene.walls) sample_walls(w, dp, pts);
    for (const auto& b : scene.solids)
        if (!b.floating.enabled) sample_solid(b, dp, pts);
    for (const auto& x : pts) others.push_back(lattice_key(x, dp));
    for (std::size_t i = 0; i < scene.solids.size(); ++i) {
        if (!scene.solids[i].floating.enabled) continue;
        std::sort(others.begin(), others.end());
        std::vector<Vec3> mine;
        sample_solid(scene.solids[i], dp, mine);
        for (const auto& x : mine) {
            const std::uint64_t k = lattice_key(x, dp);
            require(!std::binary_search(others.begin(), others.end(), k), "boundaries.boxes[" + std::to_string(i) + "]",
                    "touches another solid at (" + num(x[0]) + ", " + num(x[1]) + ", " + num(x[2]) +
                        "): a floating box may not share a particle with a wall or another box (leave dp between them)");
        }
        for (const auto& x : mine) others.push_back(lattice_key(x, dp));
    }
}

}  // namespace clsph::scene

namespace clsph {
bool Scene::has_floating() const {
    for (const auto& b : solids)
        if (b.floating.enabled) return true;
    return false;
}
}  // namespace clsph
