// What the probes measure: sample points and the reduction of their sums (gauges.hpp).
#include "probes/gauges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clsph::probes {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// The unit vector along v (Scene::validate has checked that v is finite and not zero). Scaled by
// its largest component first, so that tiny and huge normals do not under- or overflow.
Vec3 unit(const Vec3& v) {
    const double big = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    const Vec3 s{v[0] / big, v[1] / big, v[2] / big};
    const double l = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    return {s[0] / l, s[1] / l, s[2] / l};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Two unit vectors spanning the plane perpendicular to the unit vector n: u along n x (the axis
// least aligned with n), so the pair is well conditioned for every n.
std::array<Vec3, 2> plane_basis(const Vec3& n) {
    int least = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(n[k]) < std::abs(n[least])) least = k;
    Vec3 axis{0, 0, 0};
    axis[least] = 1.0;
    const Vec3 u = unit(cross(n, axis));
    return {u, cross(n, u)};
}

}  // namespace

std::vector<Vec3> face_points(const Probe& probe, double dp) {
    if (!probe.normal) return {probe.point};
    const auto [u, v] = plane_basis(unit(*probe.normal));
    // dp/2 resolves the field as finely as the particles do; size/4 puts at least the centre and
    // a ring of 12 on a small sensor; size/32 bounds a large one to about 800 points.
    const double spacing = std::max(std::min(0.5 * dp, 0.25 * probe.size), probe.size / 32.0);
    const double r = 0.5 * probe.size / spacing;  // the radius in spacings
    const int n = static_cast<int>(std::floor(r + 1e-9));
    std::vector<Vec3> out{probe.point};
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j) {
            if ((i == 0 && j == 0) || i * i + j * j > r * r * (1 + 1e-9)) continue;
            Vec3 x = probe.point;
            for (int k = 0; k < 3; ++k) x[k] += spacing * (i * u[k] + j * v[k]);
            out.push_back(x);
        }
    return out;
}

Points sample_points(const Scene& scene) {
    Points p;
    const double z0 = scene.domain.min[2], z1 = scene.domain.max[2];
    p.dz = 0.5 * scene.physics.dp;
    for (const auto& pr : scene.probes) {
        p.first.push_back(p.points.size());
        if (pr.kind == Probe::Kind::pressure) {
            const auto face = face_points(pr, scene.physics.dp);
            p.points.insert(p.points.end(), face.begin(), face.end());
        } else {
            for (std::size_t k = 0; z0 + static_cast<double>(k) * p.dz <= z1 + 1e-12; ++k)
                p.points.push_back({pr.point[0], pr.point[1], z0 + static_cast<double>(k) * p.dz});
        }
    }
    p.first.push_back(p.points.size());
    return p;
}

double water_height(const Sums* line, std::size_t count, double z0, double dz) {
    // The first fall through 1/2 from below, not the highest: spray or a drop above the gauge
    // (fluid over air) then does not read as a column of water reaching up to it.
    for (std::size_t k = 1; k < count; ++k) {
        const double f_lo = line[k - 1][0], f_hi = line[k][0];
        if (f_lo >= 0.5 && f_hi < 0.5) return z0 + dz * (static_cast<double>(k - 1) + (f_lo - 0.5) / (f_lo - f_hi));
    }
    // Dry (the fraction never reaches 1/2): no water, 0 rather than a NaN in the probe files.
    // Full to the top of the line: no surface to read.
    bool wet = false;
    for (std::size_t k = 0; k < count && !wet; ++k) wet = line[k][0] >= 0.5;
    return wet ? nan : 0.0;
}

double face_pressure(const Sums* points, std::size_t count) {
    double sum = 0;
    std::size_t wet = 0;
    for (std::size_t k = 0; k < count; ++k)
        if (points[k][0] > min_fraction) {
            sum += static_cast<double>(points[k][1]) / static_cast<double>(points[k][0]);
            ++wet;
        }
    return wet ? sum / static_cast<double>(wet) : nan;
}

std::vector<double> values(const Scene& scene, const Points& points, const std::vector<Sums>& sums) {
    std::vector<double> out;
    for (std::size_t i = 0; i < scene.probes.size(); ++i) {
        const Sums* s = sums.data() + points.first[i];
        const std::size_t n = points.first[i + 1] - points.first[i];
        if (scene.probes[i].kind == Probe::Kind::pressure)
            out.push_back(face_pressure(s, n));
        else
            out.push_back(water_height(s, n, points.points[points.first[i]][2], points.dz));
    }
    return out;
}

}  // namespace clsph::probes
