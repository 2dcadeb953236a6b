// Scene checks and the particles of a scene (boundaries, then fluid in hydrostatic equilibrium).
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "scene/lattice.hpp"
#include "scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace clsph {
namespace {

std::string vec(const Vec3& v) {
    std::ostringstream o;
    o << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
    return o.str();
}

void require(bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw SceneError(key + ": " + what);
}

double fluid_height(const Scene& s) {
    double h = 0.0;
    for (const auto& f : s.fluids) h = std::max(h, f.surface.value_or(f.max[2]) - f.min[2]);
    for (const auto& m : s.meshes)
        if (m.fluid) h = std::max(h, s.domain.max[2] - s.domain.min[2]);  // bounded by the domain
    return h;
}

}  // namespace

double Scene::sound_speed() const {
    if (physics.c0 > 0) return physics.c0;
    const double g = std::sqrt(physics.gravity[0] * physics.gravity[0] + physics.gravity[1] * physics.gravity[1] +
                               physics.gravity[2] * physics.gravity[2]);
    const double H = fluid_height(*this);
    if (!(g * H > 0))
        throw SceneError("physics.c0: without gravity or fluid height the speed of sound cannot be derived; set it");
    return physics.coefsound * std::sqrt(g * H);
}

void Scene::validate() const {
    const auto& p = physics;
    auto finite_pos = [](double v) { return std::isfinite(v) && v > 0; };
    require(finite_pos(p.dp), "physics.dp", "must be a positive number (got " + std::to_string(p.dp) + ")");
    require(finite_pos(p.hdp), "physics.hdp", "must be positive");
    require(finite_pos(p.rho0), "physics.rho0", "must be positive");
    require(p.gamma == 7.0, "physics.gamma", "only 7 is supported (the kernels expand the power)");
    require(p.cfl > 0 && p.cfl <= 1.0, "physics.cfl", "must be in (0, 1]");
    require(p.alpha >= 0 && std::isfinite(p.alpha), "physics.alpha", "must be >= 0");
    require(p.delta >= 0 && std::isfinite(p.delta), "physics.delta", "must be >= 0");
    require(p.density_min < 1.0 && p.density_max > 1.0 && p.density_min > 0, "physics.density_min",
            "the density band must contain 1 (as a fraction of rho0)");
    for (int k = 0; k < 3; ++k)
        require(domain.max[k] > domain.min[k], "domain.max", "must be greater than domain.min on every axis");
    require(run.output_every > 0, "run.output_every", "must be positive");
    require(run.end_time >= 0 && std::isfinite(run.end_time), "run.end_time", "must be >= 0");
    require(run.probe_every >= 1, "run.probe_every", "must be >= 1");
    auto inside = [&](const Vec3& a) {
        for (int k = 0; k < 3; ++k)
            if (a[k] < domain.min[k] - 1e-9 || a[k] > domain.max[k] + 1e-9) return false;
        return true;
    };
    for (std::size_t i = 0; i < fluids.size(); ++i) {
        const auto& f = fluids[i];
        const std::string key = "fluid[" + std::to_string(i) + "]";
        for (int k = 0; k < 3; ++k) require(f.max[k] > f.min[k], key + ".max", "must be greater than min on every axis");
        require(inside(f.min) && inside(f.max), key,
                "block " + vec(f.min) + " - " + vec(f.max) + " is not inside the domain " + vec(domain.min) + " - " +
                    vec(domain.max));
        for (std::size_t j = 0; j < i; ++j) {
            const auto& g = fluids[j];
            bool overlap = true;
            for (int k = 0; k < 3; ++k) overlap = overlap && f.min[k] < g.max[k] && g.min[k] < f.max[k];
            require(!overlap, key, "overlaps fluid[" + std::to_string(j) + "]");
        }
    }
    for (std::size_t i = 0; i < walls.size(); ++i) {
        const std::string key = "boundaries.walls[" + std::to_string(i) + "]";
        require(walls[i].layers >= 1 && walls[i].layers <= 16, key + ".layers", "must be 1 to 16");
        for (int k = 0; k < 3; ++k) require(walls[i].max[k] > walls[i].min[k], key + ".max", "must be greater than min");
    }
    for (std::size_t i = 0; i < solids.size(); ++i) {
        const std::string key = "boundaries.boxes[" + std::to_string(i) + "]";
        for (int k = 0; k < 3; ++k)
            require(solids[i].max[k] > solids[i].min[k], key + ".max", "must be greater than min");
    }
    for (std::size_t i = 0; i < probes.size(); ++i)
        require(inside(probes[i].kind == Probe::Kind::height
                           ? Vec3{probes[i].point[0], probes[i].point[1], domain.min[2]}
                           : probes[i].point),
                "probes[" + std::to_string(i) + "].point", "is outside the domain");
    // Estimated particle count before sampling, so an absurd dp fails fast and clearly.
    double volume = 0.0;
    for (const auto& f : fluids) volume += (f.max[0] - f.min[0]) * (f.max[1] - f.min[1]) * (f.max[2] - f.min[2]);
    const double estimate = volume / (p.dp * p.dp * p.dp);
    if (!(estimate < 1.0e9)) {
        std::ostringstream o;  // a plain whole number, however large (an integer cast would overflow)
        o << std::fixed << std::setprecision(0) << "gives about " << estimate
          << " fluid particles; clsph ids allow at most 1e9";
        throw SceneError("physics.dp: " + o.str());
    }
    (void)sound_speed();
}

Particles Scene::build_particles() const {
    validate();
    const double dp = physics.dp;
    const double c0 = sound_speed(), rho0 = physics.rho0, gamma = physics.gamma;
    const double B = c0 * c0 * rho0 / gamma;
    std::vector<Vec3> boundary, fluid;
    for (const auto& w : walls) scene::sample_walls(w, dp, boundary);
    for (const auto& b : solids) scene::sample_solid(b, dp, boundary);
    for (const auto& m : meshes) scene::sample_mesh(m, dp, boundary, fluid);

    for (const auto& f : fluids) {
        const std::int64_t i0 = scene::lattice_first(f.min[0], dp), i1 = scene::lattice_last(f.max[0], dp);
        const std::int64_t j0 = scene::lattice_first(f.min[1], dp), j1 = scene::lattice_last(f.max[1], dp);
        const std::int64_t k0 = scene::lattice_first(f.min[2], dp), k1 = scene::lattice_last(f.max[2], dp);
        for (std::int64_t i = i0; i <= i1; ++i)
            for (std::int64_t j = j0; j <= j1; ++j)
                for (std::int64_t k = k0; k <= k1; ++k)
                    fluid.push_back({static_cast<double>(i) * dp, static_cast<double>(j) * dp, static_cast<double>(k) * dp});
    }
    // Fluid keeps at least dp from every boundary particle (a tolerance for lattice round-off).
    if (!boundary.empty()) {
        const scene::PointHash hash(boundary, dp);
        fluid.erase(std::remove_if(fluid.begin(), fluid.end(),
                                   [&](const Vec3& x) { return hash.any_within(x, dp * (1.0 - 1e-6)); }),
                    fluid.end());
    }

    Particles out;
    out.id.reserve(boundary.size() + fluid.size());
    std::uint32_t next = 0;
    // Boundary particles start in hydrostatic equilibrium with the fluid beside or above them
    // (within a kernel support of a block's footprint), so the fluid does not first fall into an
    // unpressurised wall and bounce (a large, slowly damped transient with DBC).
    const double reach = physics.support();
    for (const auto& x : boundary) {
        double p = 0.0;
        for (const auto& f : fluids) {
            const bool beside = x[0] >= f.min[0] - reach && x[0] <= f.max[0] + reach && x[1] >= f.min[1] - reach &&
                                x[1] <= f.max[1] + reach;
            if (beside) p = std::max(p, rho0 * -physics.gravity[2] * (f.surface.value_or(f.max[2]) - x[2]));
        }
        const double rho = rho0 * std::pow(1.0 + p / B, 1.0 / gamma);
        out.push_back(next++, ParticleType::boundary, x, {0, 0, 0}, static_cast<float>(rho), static_cast<float>(p));
    }
    for (const auto& x : fluid) {
        // Hydrostatic: p = rho0 |g_z| (surface - z) below the surface of the block the point is in.
        double surface = x[2];
        Vec3 v{0, 0, 0};
        for (const auto& f : fluids) {
            bool in = true;
            for (int k = 0; k < 3; ++k) in = in && x[k] >= f.min[k] - 1e-9 && x[k] <= f.max[k] + 1e-9;
            if (in) {
                surface = f.surface.value_or(f.max[2]);
                v = f.velocity;
                break;
            }
        }
        const double p = std::max(0.0, rho0 * -physics.gravity[2] * (surface - x[2]));
        const double rho = rho0 * std::pow(1.0 + p / B, 1.0 / gamma);
        out.push_back(next++, ParticleType::fluid, x,
                      {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])},
                      static_cast<float>(rho), static_cast<float>(p));
    }
    return out;
}

}  // namespace clsph
