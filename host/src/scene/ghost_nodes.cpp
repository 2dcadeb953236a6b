#include "scene/ghost_nodes.hpp"

#include "scene/lattice.hpp"
#include "scene/mesh.hpp"
#include "scene/mesh_grid.hpp"
#include "scene/mesh_formats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace clsph::scene {
namespace {

// Boundary points of the scene with their ghost-node offsets, sorted by lattice key (first wins).
class Mirrors {
public:
    explicit Mirrors(double dp) : dp_(dp) {}
    void add(const Vec3& x, const Vec3& m) { entries_.push_back({lattice_key(x, dp_), m}); }
    void finish() {
        std::stable_sort(entries_.begin(), entries_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        entries_.erase(std::unique(entries_.begin(), entries_.end(),
                                   [](const auto& a, const auto& b) { return a.first == b.first; }),
                       entries_.end());
    }
    const Vec3* find(const Vec3& x) const {
        const std::uint64_t k = lattice_key(x, dp_);
        const auto it = std::lower_bound(entries_.begin(), entries_.end(), k,
                                         [](const auto& e, std::uint64_t v) { return e.first < v; });
        return it != entries_.end() && it->first == k ? &it->second : nullptr;
    }

private:
    double dp_;
    std::vector<std::pair<std::uint64_t, Vec3>> entries_;
};

// Walls: the particle lies beyond (or on) each selected face it belongs to.
void wall_mirrors(const BoxWalls& w, double dp, Mirrors& out) {
    std::vector<Vec3> pts;
    sample_walls(w, dp, pts);
    const double tol = 1e-6 * dp;
    for (const auto& x : pts) {
        Vec3 m{0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            if ((w.faces & (1u << (2 * a))) && x[a] <= w.min[a] + tol)
                m[a] = 2.0 * (w.min[a] + 0.5 * dp - x[a]);
            else if ((w.faces & (1u << (2 * a + 1))) && x[a] >= w.max[a] - tol)
                m[a] = -2.0 * (x[a] - (w.max[a] - 0.5 * dp));
        }
        out.add(x, m);
    }
}

// Solid boxes: the faces whose layers hold the particle and which face open space (the lattice
// point just beyond the face, opposite the particle, is no boundary particle). A floating box
// moves away from whatever covers it at rest, so none of its faces counts as covered; and only
// its particles within a support of a face mirror across it (deeper ones no fluid reaches: they
// interpolate at themselves, rho0), so that its ghost nodes stay near it wherever it goes.
void solid_mirrors(const SolidBox& b, double dp, double support, const PointHash& boundary, Mirrors& out) {
    std::vector<Vec3> pts;
    sample_solid(b, dp, pts);
    double band = (b.layers > 0 ? b.layers : 1 << 20) * dp - 1e-6 * dp;
    if (b.floating.enabled) band = std::min(band, support - 1e-6 * dp);
    for (const auto& x : pts) {
        Vec3 m{0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            const double to_min = x[a] - b.min[a], to_max = b.max[a] - x[a];
            const bool min_side = to_min <= to_max;
            const double depth = min_side ? to_min : to_max;
            if (depth >= band) continue;
            Vec3 beyond = x;
            beyond[a] += (min_side ? -1.0 : 1.0) * (depth + dp);
            if (!b.floating.enabled && boundary.any_within(beyond, 1e-3 * dp)) continue;  // covered: no fluid can be there
            m[a] = (min_side ? -2.0 : 2.0) * (depth + 0.5 * dp);
        }
        out.add(x, m);
    }
}

// Meshes: along the direction from the particle to the nearest surface point.
void mesh_mirrors(const MeshObject& mo, double dp, Mirrors& out) {
    std::vector<Vec3> pts, unused;
    sample_mesh(mo, dp, pts, unused);
    TriangleMesh mesh = read_closed_mesh(mo.path);
    place_mesh(mesh, mo);
    const double reach = (mo.layers + 1) * dp;
    const TriangleGrid grid(mesh, std::max(reach, dp));
    std::vector<std::uint64_t> keys;
    for (const auto& x : pts) keys.push_back(lattice_key(x, dp));
    std::sort(keys.begin(), keys.end());
    for (const auto& x : pts) {
        Vec3 q{};
        Vec3 m{0, 0, 0};
        if (grid.nearest(x, reach, q)) {
            Vec3 d{q[0] - x[0], q[1] - x[1], q[2] - x[2]};
            const double depth = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (depth > 1e-6 * dp) {
                const double s = 2.0 * (depth + 0.5 * dp) / depth;
                m = {s * d[0], s * d[1], s * d[2]};
            } else {
                // On the surface: outward is where a small step leaves the mesh, i.e. where the
                // nearest surface point is no longer within the step (tried along +-x, +-y, +-z and
                // the mean of the open directions).
                Vec3 n{0, 0, 0};
                for (int a = 0; a < 3; ++a)
                    for (double sgn : {-1.0, 1.0}) {
                        Vec3 y = x;
                        y[a] += sgn * dp;
                        if (!std::binary_search(keys.begin(), keys.end(), lattice_key(y, dp))) n[a] += sgn;
                    }
                const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                if (len > 0)
                    for (int a = 0; a < 3; ++a) m[a] = dp * n[a] / len;
            }
        }
        out.add(x, m);
    }
}

}  // namespace

std::vector<std::array<float, 3>> ghost_node_offsets(const Scene& scene, const Particles& p) {
    const double dp = scene.physics.dp;
    std::vector<Vec3> all;
    for (const auto& w : scene.walls) sample_walls(w, dp, all);
    for (const auto& b : scene.solids) sample_solid(b, dp, all);
    Mirrors mirrors(dp);
    for (const auto& w : scene.walls) wall_mirrors(w, dp, mirrors);
    if (!scene.solids.empty()) {
        const PointHash boundary(all, dp);
        for (const auto& b : scene.solids) solid_mirrors(b, dp, scene.physics.support(), boundary, mirrors);
    }
    for (const auto& m : scene.meshes)
        if (!m.fluid) mesh_mirrors(m, dp, mirrors);
    mirrors.finish();
    std::vector<std::array<float, 3>> out(p.size(), {0.0f, 0.0f, 0.0f});
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary) continue;
        if (const Vec3* m = mirrors.find(p.position[i]))
            out[i] = {static_cast<float>((*m)[0]), static_cast<float>((*m)[1]), static_cast<float>((*m)[2])};
    }
    return out;
}

}  // namespace clsph::scene
