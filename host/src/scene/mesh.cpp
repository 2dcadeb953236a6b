// Sampling a closed triangle mesh (any format of scene/mesh_formats.hpp) onto the dp lattice.
//
// Inside or outside: a lattice point is inside when the vertical ray above it crosses the surface
// an odd number of times. The ray starts a tiny, irrationally proportioned offset away from the
// point, so that it passes through no vertex or edge even when the mesh itself sits on the
// lattice (a cube from 0 to 1 at dp = 0.1); the offset can only misjudge points closer to the
// surface than itself, and those are decided by distance: a point within 1e-6 dp of the surface
// is on it, and counts as inside. A lattice-aligned unit cube therefore holds (1/dp + 1)^3 points,
// as a solid box of the same size does.
#include "scene/mesh.hpp"

#include "clsph/error.hpp"
#include "scene/lattice.hpp"
#include "scene/mesh_grid.hpp"
#include "scene/mesh_formats.hpp"

#include <algorithm>
#include <cmath>

namespace clsph::scene {
namespace {

// Fractions of dp; their ratios are irrational so no lattice line or diagonal lines up with the ray.
constexpr double ray_dx = 3.14159265358979e-8, ray_dy = 2.71828182845905e-8, ray_dz = 1.41421356237310e-8;
constexpr double on_surface = 1e-6;

// cos and sin of an angle in degrees, exact at multiples of 90.
void cos_sin(double degrees, double& c, double& s) {
    const double a = std::fmod(degrees, 360.0);
    if (a == 0) return void((c = 1, s = 0));
    if (a == 90 || a == -270) return void((c = 0, s = 1));
    if (a == 180 || a == -180) return void((c = -1, s = 0));
    if (a == 270 || a == -90) return void((c = 0, s = -1));
    const double r = a * (std::acos(-1.0) / 180.0);
    c = std::cos(r);
    s = std::sin(r);
}

}  // namespace

void place_mesh(TriangleMesh& mesh, const MeshObject& m) {
    const bool rotated = m.rotate[0] != 0 || m.rotate[1] != 0 || m.rotate[2] != 0;
    for (auto& v : mesh.vertices) {
        for (int k = 0; k < 3; ++k) v[k] *= m.scale;
        if (rotated)
            for (int axis = 0; axis < 3; ++axis) {  // x, then y, then z
                double c = 1, s = 0;
                cos_sin(m.rotate[axis], c, s);
                const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane it turns: yz, zx, xy
                const double a = v[i], b = v[j];
                v[i] = c * a - s * b;
                v[j] = s * a + c * b;
            }
        for (int k = 0; k < 3; ++k) v[k] += m.translate[k];
    }
}

void sample_mesh(const MeshObject& m, double dp, std::vector<Vec3>& boundary, std::vector<Vec3>& fluid) {
    if (!(m.scale > 0) || !std::isfinite(m.scale)) throw SceneError(m.path + ": the mesh scale must be positive");
    if (!m.fluid && m.layers < 1) throw SceneError(m.path + ": a boundary mesh needs at least 1 layer");
    TriangleMesh mesh = read_closed_mesh(m.path);
    place_mesh(mesh, m);

    Vec3 lo = mesh.vertices[0], hi = mesh.vertices[0];
    for (const auto& v : mesh.vertices)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
    const double eps = on_surface * dp;
    std::int64_t first[3], last[3];
    double points = 1.0;  // lattice points in the bounding box, checked before any is visited
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(lo[k]) || !std::isfinite(hi[k]) || std::abs(lo[k]) > max_coordinate ||
            std::abs(hi[k]) > max_coordinate)
            throw SceneError(m.path + ": after scale, rotate and translate the mesh reaches beyond 1e9 m");
        points *= (hi[k] - lo[k]) / dp + 1.0;
    }
    if (!(points < 1e9))
        throw SceneError(m.path + ": the mesh's bounding box holds about " + std::to_string(static_cast<long long>(std::min(points, 9e18))) +
                         " points of the dp lattice; at most 1e9 are sampled");
    for (int k = 0; k < 3; ++k) {
        first[k] = lattice_first(lo[k] - eps, dp);
        last[k] = lattice_last(hi[k] + eps, dp);
    }

    // Boundary layers: points closer than `layers` dp to the surface (less a hair, so that on a
    // lattice-aligned face the layer at exactly layers * dp is reliably left out).
    const double band = (m.layers - on_surface) * dp;
    const TriangleGrid near(mesh, m.fluid ? 2.0 * dp : std::max(band, dp));
    const VerticalRays rays(mesh, dp);
    std::vector<double> cross;
    for (std::int64_t i = first[0]; i <= last[0]; ++i)
        for (std::int64_t j = first[1]; j <= last[1]; ++j) {
            const double x = static_cast<double>(i) * dp, y = static_cast<double>(j) * dp;
            rays.crossings(x + ray_dx * dp, y + ray_dy * dp, cross);
            std::size_t below = 0;  // crossings at or below the current point (they come sorted)
            for (std::int64_t k = first[2]; k <= last[2]; ++k) {
                const Vec3 p{x, y, static_cast<double>(k) * dp};
                while (below < cross.size() && cross[below] <= p[2] + ray_dz * dp) ++below;
                const bool odd = (cross.size() - below) % 2 == 1;
                const bool inside = odd || near.any_within(p, eps);
                if (!inside) continue;
                if (m.fluid)
                    fluid.push_back(p);
                else if (near.any_within(p, band))
                    boundary.push_back(p);
            }
        }
}

}  // namespace clsph::scene
