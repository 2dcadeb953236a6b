// Spatial look-ups on a triangle mesh: "is any triangle within r of this point?" through a
// uniform grid of triangle bounding boxes, and the vertical rays that decide inside and outside.
#pragma once
#include "scene/mesh_obj.hpp"

#include <cstdint>
#include <vector>

namespace clsph::scene {

// The point of the triangle abc closest to p (by Voronoi region of the triangle), and its squared distance.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
double point_triangle_distance_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class TriangleGrid {
public:
    // `cell` is a hint: the grid grows it when the mesh's box would need too many cells.
    TriangleGrid(const TriangleMesh& mesh, double cell);
    bool any_within(const Vec3& p, double r) const;
    // The closest point of the surface to p, among triangles closer than r; false when none is.
    bool nearest(const Vec3& p, double r, Vec3& closest) const { return nearest(p, r, closest, false); }

private:
    std::int64_t cell_index(double x, int axis) const;
    bool nearest(const Vec3& p, double r, Vec3& closest, bool any) const;
    const TriangleMesh& mesh_;
    Vec3 origin_{};
    double cell_ = 1.0;
    std::int64_t n_[3] = {1, 1, 1};
    std::vector<std::uint32_t> start_;      // per cell, into items_ (CSR)
    std::vector<std::uint32_t> items_;      // triangle indices
};

// The heights z at which the vertical line through (x, y) crosses the mesh, sorted. Triangles seen
// edge-on (vertical) are skipped; the caller offsets (x, y) by a tiny irrational amount so that the
// line passes through no edge or vertex in practice.
class VerticalRays {
public:
    VerticalRays(const TriangleMesh& mesh, double cell);
    void crossings(double x, double y, std::vector<double>& out) const;

private:
    const TriangleMesh& mesh_;
    double x0_ = 0, y0_ = 0, cell_ = 1.0;
    std::int64_t nx_ = 1, ny_ = 1;
    std::vector<std::uint32_t> start_, items_;
};

}  // namespace clsph::scene
