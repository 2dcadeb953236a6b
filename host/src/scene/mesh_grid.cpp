#include "scene/mesh_grid.hpp"

#include <algorithm>
#include <cmath>

namespace clsph::scene {
namespace {

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 along(const Vec3& a, const Vec3& d, double t) { return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]}; }
double dist_sq(const Vec3& a, const Vec3& b) { return dot(sub(a, b), sub(a, b)); }

Vec3 segment_closest(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = sub(b, a);
    const double len = dot(ab, ab);
    const double t = len > 0 ? std::clamp(dot(sub(p, a), ab) / len, 0.0, 1.0) : 0.0;
    return along(a, ab, t);
}

// Builds a CSR table: cell -> triangles, from a function giving each triangle's cell range.
template <class Range>
void fill_cells(std::size_t cells, std::size_t triangles, Range range, std::vector<std::uint32_t>& start,
                std::vector<std::uint32_t>& items) {
    start.assign(cells + 1, 0);
    for (std::uint32_t t = 0; t < triangles; ++t) range(t, [&](std::size_t c) { ++start[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    items.resize(start[cells]);
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::uint32_t t = 0; t < triangles; ++t) range(t, [&](std::size_t c) { items[next[c]++] = t; });
}

void bounds(const TriangleMesh& m, Vec3& lo, Vec3& hi) {
    lo = hi = m.vertices.at(0);
    for (const auto& v : m.vertices)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Which feature of the triangle (vertex, edge or face) is closest, from the signs of the
    // projections of p onto the edges (the Voronoi regions of the triangle).
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double sum = va + vb + vc;
    if (!(std::abs(sum) > 0)) {  // collinear vertices: no face, only edges
        const Vec3 e[3] = {segment_closest(p, a, b), segment_closest(p, b, c), segment_closest(p, a, c)};
        const double d[3] = {dist_sq(p, e[0]), dist_sq(p, e[1]), dist_sq(p, e[2])};
        return e[std::min_element(d, d + 3) - d];
    }
    const double v = vb / sum, w = vc / sum;
    return {a[0] + v * ab[0] + w * ac[0], a[1] + v * ab[1] + w * ac[1], a[2] + v * ab[2] + w * ac[2]};
}

double point_triangle_distance_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    return dist_sq(p, closest_point_on_triangle(p, a, b, c));
}

TriangleGrid::TriangleGrid(const TriangleMesh& mesh, double cell) : mesh_(mesh), cell_(cell) {
    Vec3 lo, hi;
    bounds(mesh, lo, hi);
    // A dense grid over the mesh's box; coarser when it would exceed 16M cells.
    for (;;) {
        std::int64_t total = 1;
        for (int k = 0; k < 3; ++k) {
            n_[k] = static_cast<std::int64_t>(std::floor((hi[k] - lo[k]) / cell_)) + 3;
            total *= n_[k];
        }
        if (total <= (std::int64_t{1} << 24)) break;
        cell_ *= 1.25;
    }
    for (int k = 0; k < 3; ++k) origin_[k] = lo[k] - cell_;
    const auto cells = static_cast<std::size_t>(n_[0] * n_[1] * n_[2]);
    fill_cells(cells, mesh.triangles.size(),
               [&](std::uint32_t t, auto&& add) {
                   std::int64_t a[3], b[3];
                   for (int k = 0; k < 3; ++k) {
                       const auto& tri = mesh_.triangles[t];
                       const double lo_k = std::min({mesh_.vertices[tri[0]][k], mesh_.vertices[tri[1]][k], mesh_.vertices[tri[2]][k]});
                       const double hi_k = std::max({mesh_.vertices[tri[0]][k], mesh_.vertices[tri[1]][k], mesh_.vertices[tri[2]][k]});
                       a[k] = cell_index(lo_k, k);
                       b[k] = cell_index(hi_k, k);
                   }
                   for (auto i = a[0]; i <= b[0]; ++i)
                       for (auto j = a[1]; j <= b[1]; ++j)
                           for (auto l = a[2]; l <= b[2]; ++l) add(static_cast<std::size_t>((i * n_[1] + j) * n_[2] + l));
               },
               start_, items_);
}

std::int64_t TriangleGrid::cell_index(double x, int axis) const {
    const auto c = static_cast<std::int64_t>(std::floor((x - origin_[axis]) / cell_));
    return std::clamp<std::int64_t>(c, 0, n_[axis] - 1);
}

bool TriangleGrid::any_within(const Vec3& p, double r) const {
    Vec3 unused{};
    return nearest(p, r, unused, true);
}

bool TriangleGrid::nearest(const Vec3& p, double r, Vec3& closest, bool any) const {
    std::int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) {
        // Cells wholly beyond the grid hold no triangle: a point farther than r from the box is done.
        if (p[k] + r < origin_[k] || p[k] - r > origin_[k] + static_cast<double>(n_[k]) * cell_) return false;
        a[k] = cell_index(p[k] - r, k);
        b[k] = cell_index(p[k] + r, k);
    }
    double best = r * r;
    bool found = false;
    for (auto i = a[0]; i <= b[0]; ++i)
        for (auto j = a[1]; j <= b[1]; ++j)
            for (auto l = a[2]; l <= b[2]; ++l) {
                const auto c = static_cast<std::size_t>((i * n_[1] + j) * n_[2] + l);
                for (auto s = start_[c]; s < start_[c + 1]; ++s) {
                    const auto& t = mesh_.triangles[items_[s]];
                    const Vec3 q = closest_point_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
                    const double d2 = dist_sq(p, q);
                    if (d2 < best) {
                        if (any) return true;
                        best = d2;
                        closest = q;
                        found = true;
                    }
                }
            }
    return found;
}

VerticalRays::VerticalRays(const TriangleMesh& mesh, double cell) : mesh_(mesh), cell_(cell) {
    Vec3 lo, hi;
    bounds(mesh, lo, hi);
    for (;;) {
        nx_ = static_cast<std::int64_t>(std::floor((hi[0] - lo[0]) / cell_)) + 1;
        ny_ = static_cast<std::int64_t>(std::floor((hi[1] - lo[1]) / cell_)) + 1;
        if (nx_ * ny_ <= (std::int64_t{1} << 22)) break;
        cell_ *= 1.25;
    }
    x0_ = lo[0];
    y0_ = lo[1];
    auto index = [&](double v, double v0, std::int64_t n) {
        return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((v - v0) / cell_)), 0, n - 1);
    };
    fill_cells(static_cast<std::size_t>(nx_ * ny_), mesh.triangles.size(),
               [&](std::uint32_t t, auto&& add) {
                   const auto& tri = mesh_.triangles[t];
                   const Vec3 &a = mesh_.vertices[tri[0]], &b = mesh_.vertices[tri[1]], &c = mesh_.vertices[tri[2]];
                   const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                   if (area2 == 0) return;  // seen edge-on from above: a vertical ray never crosses it
                   const auto i0 = index(std::min({a[0], b[0], c[0]}), x0_, nx_), i1 = index(std::max({a[0], b[0], c[0]}), x0_, nx_);
                   const auto j0 = index(std::min({a[1], b[1], c[1]}), y0_, ny_), j1 = index(std::max({a[1], b[1], c[1]}), y0_, ny_);
                   for (auto i = i0; i <= i1; ++i)
                       for (auto j = j0; j <= j1; ++j) add(static_cast<std::size_t>(i * ny_ + j));
               },
               start_, items_);
}

void VerticalRays::crossings(double x, double y, std::vector<double>& out) const {
    out.clear();
    const double fi = std::floor((x - x0_) / cell_), fj = std::floor((y - y0_) / cell_);
    if (fi < 0 || fj < 0 || fi >= static_cast<double>(nx_) || fj >= static_cast<double>(ny_)) return;
    const auto c = static_cast<std::size_t>(static_cast<std::int64_t>(fi) * ny_ + static_cast<std::int64_t>(fj));
    for (auto s = start_[c]; s < start_[c + 1]; ++s) {
        const auto& tri = mesh_.triangles[items_[s]];
        const Vec3 &a = mesh_.vertices[tri[0]], &b = mesh_.vertices[tri[1]], &cc = mesh_.vertices[tri[2]];
        // Signed areas of (x, y) with each edge; all of one sign: the line passes through the face.
        const double ea = (cc[0] - b[0]) * (y - b[1]) - (cc[1] - b[1]) * (x - b[0]);
        const double eb = (a[0] - cc[0]) * (y - cc[1]) - (a[1] - cc[1]) * (x - cc[0]);
        const double ec = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
        const bool inside = (ea > 0 && eb > 0 && ec > 0) || (ea < 0 && eb < 0 && ec < 0);
        if (!inside) continue;
        const double sum = ea + eb + ec;  // twice the projected area; the e's are barycentric weights
        out.push_back((ea * a[2] + eb * b[2] + ec * cc[2]) / sum);
    }
    std::sort(out.begin(), out.end());
}

}  // namespace clsph::scene
