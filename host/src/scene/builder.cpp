// Scene checks and the particles of a scene (boundaries, then fluid in hydrostatic equilibrium).
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "scene/lattice.hpp"
#include "scene/lattice_plan.hpp"
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

Particles Scene::build_particles() const {
    // Scenes of lattice pieces only: the plan the devices generate from (scene/lattice_plan.hpp),
    // ordered by the split axis. Scenes with meshes: sampled here, in the scene's order.
    if (scene::LatticePlan::supports(*this)) return scene::LatticePlan::make(*this).particles();
    return scene::sampled_particles(*this);
}

Scene::Count Scene::count_particles() const {
    Count c;
    if (scene::LatticePlan::supports(*this)) {
        const auto plan = scene::LatticePlan::make(*this);
        c.fluid = plan.fluid_count;
        c.boundary = plan.boundary_count;
        return c;
    }
    const Particles p = build_particles();
    for (auto t : p.type) (t == ParticleType::fluid ? c.fluid : c.boundary) += 1;
    return c;
}

Particles scene::sampled_particles(const Scene& scene) {
    const auto& physics = scene.physics;
    const auto& domain = scene.domain;
    const auto& fluids = scene.fluids;
    const auto& walls = scene.walls;
    const auto& solids = scene.solids;
    const auto& meshes = scene.meshes;
    auto sound_speed = [&] { return scene.sound_speed(); };
    scene.validate();
    const double dp = physics.dp;
    const double c0 = sound_speed(), rho0 = physics.rho0, gamma = physics.gamma;
    const double B = c0 * c0 * rho0 / gamma;
    std::vector<Vec3> boundary, fluid;
    std::vector<std::size_t> origin;  // per fluid point: its block, or fluids.size() + its mesh
    for (const auto& w : walls) scene::sample_walls(w, dp, boundary);
    for (const auto& b : solids) scene::sample_solid(b, dp, boundary);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const std::size_t b0 = boundary.size(), f0 = fluid.size();
        try {
            scene::sample_mesh(meshes[m], dp, boundary, fluid);
        } catch (const SceneError& e) {
            throw SceneError("boundaries.meshes[" + std::to_string(m) + "].path: " + e.what());
        }
        origin.resize(fluid.size(), fluids.size() + m);
        // Where a mesh lands is known only once it is read: all of it must be in the domain.
        auto outside = [&](const Vec3& x) {
            for (int k = 0; k < 3; ++k)
                if (!(x[k] >= domain.min[k] - 1e-9 * dp && x[k] <= domain.max[k] + 1e-9 * dp)) return true;
            return false;
        };
        auto check = [&](const std::vector<Vec3>& points, std::size_t from) {
            for (std::size_t i = from; i < points.size(); ++i)
                if (outside(points[i]))
                    require(false, "boundaries.meshes[" + std::to_string(m) + "]",
                            "the mesh reaches outside the domain " + vec(domain.min) + " - " + vec(domain.max) +
                                " (a particle at " + vec(points[i]) + "; particles outside the domain are removed)");
        };
        check(boundary, b0);
        check(fluid, f0);
    }

    for (std::size_t b = 0; b < fluids.size(); ++b) {
        const auto& f = fluids[b];
        const std::int64_t i0 = scene::lattice_first(f.min[0], dp), i1 = scene::lattice_last(f.max[0], dp);
        const std::int64_t j0 = scene::lattice_first(f.min[1], dp), j1 = scene::lattice_last(f.max[1], dp);
        const std::int64_t k0 = scene::lattice_first(f.min[2], dp), k1 = scene::lattice_last(f.max[2], dp);
        for (std::int64_t i = i0; i <= i1; ++i)
            for (std::int64_t j = j0; j <= j1; ++j)
                for (std::int64_t k = k0; k <= k1; ++k) {
                    fluid.push_back({static_cast<double>(i) * dp, static_cast<double>(j) * dp, static_cast<double>(k) * dp});
                    origin.push_back(b);
                }
    }
    // Fluid keeps at least dp from every boundary particle (a tolerance for lattice round-off).
    std::vector<std::size_t> made(fluids.size() + meshes.size(), 0), kept(made.size(), 0);
    for (const auto o : origin) ++made[o];
    {
        const scene::PointHash hash(boundary, dp);
        std::size_t n = 0;
        for (std::size_t i = 0; i < fluid.size(); ++i) {
            if (!boundary.empty() && hash.any_within(fluid[i], dp * (1.0 - 1e-6))) continue;
            fluid[n] = fluid[i];
            origin[n] = origin[i];
            ++kept[origin[i]];
            ++n;
        }
        fluid.resize(n);
        origin.resize(n);
    }
    // A fluid block or mesh with no particle left is a mistake, not a scene with less fluid.
    for (std::size_t b = 0; b < made.size(); ++b) {
        if (kept[b] > 0) continue;
        if (b < fluids.size())
            require(false, "fluid[" + std::to_string(b) + "]",
                    "no fluid particle is left in the block " + vec(fluids[b].min) + " - " + vec(fluids[b].max) + ": each of its " +
                        std::to_string(made[b]) +
                        " lattice points is within dp of a boundary particle (it lies inside or against a solid box, "
                        "a wall or a mesh)");
        else if (meshes[b - fluids.size()].fluid)
            require(false, "boundaries.meshes[" + std::to_string(b - fluids.size()) + "]",
                    made[b] == 0 ? "the fluid mesh holds no point of the dp lattice (dp = " + std::to_string(dp) + " m)"
                                 : "no fluid particle is left in the fluid mesh: each lattice point inside is within dp "
                                   "of a boundary particle");
    }
    require(!fluid.empty(), "fluid", "the scene has no fluid particle");
    const scene::FootprintIndex blocks(fluids, physics.support());

    Particles out;
    out.id.reserve(boundary.size() + fluid.size());
    std::uint32_t next = 0;
    // Boundary particles start in hydrostatic equilibrium with the fluid beside or above them
    // (within a kernel support of a block's footprint), so the fluid does not first fall into an
    // unpressurised wall and bounce (a large, slowly damped transient with DBC).
    const double reach = physics.support();
    for (const auto& x : boundary) {
        double p = 0.0;
        blocks.each_candidate(x[0], x[1], [&](std::size_t b) {
            const auto& f = fluids[b];
            const bool beside = x[0] >= f.min[0] - reach && x[0] <= f.max[0] + reach && x[1] >= f.min[1] - reach &&
                                x[1] <= f.max[1] + reach;
            if (beside) p = std::max(p, rho0 * -physics.gravity[2] * (f.surface.value_or(f.max[2]) - x[2]));
            return true;
        });
        const double rho = rho0 * std::pow(1.0 + p / B, 1.0 / gamma);
        out.push_back(next++, ParticleType::boundary, x, {0, 0, 0}, static_cast<float>(rho), static_cast<float>(p));
    }
    for (const auto& x : fluid) {
        // Hydrostatic: p = rho0 |g_z| (surface - z) below the surface of the block the point is in.
        double surface = x[2];
        Vec3 v{0, 0, 0};
        // The first block (in the scene's order) the point is in.
        blocks.each_candidate(x[0], x[1], [&](std::size_t b) {
            const auto& f = fluids[b];
            bool in = true;
            for (int k = 0; k < 3; ++k) in = in && x[k] >= f.min[k] - 1e-9 && x[k] <= f.max[k] + 1e-9;
            if (!in) return true;
            surface = f.surface.value_or(f.max[2]);
            v = f.velocity;
            return false;
        });
        const double p = std::max(0.0, rho0 * -physics.gravity[2] * (surface - x[2]));
        const double rho = rho0 * std::pow(1.0 + p / B, 1.0 / gamma);
        out.push_back(next++, ParticleType::fluid, x,
                      {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])},
                      static_cast<float>(rho), static_cast<float>(p));
    }
    return out;
}

}  // namespace clsph
