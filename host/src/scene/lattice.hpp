// Sampling geometry onto the dp lattice (points at integer multiples of dp on each axis), and the
// host-side spatial hash used to keep fluid at least dp from every boundary particle.
#pragma once
#include "clsph/scene.hpp"

#include <cstdint>
#include <vector>

namespace clsph::scene {

// Lattice indices k with min <= k * dp <= max (a tolerance of 1e-9 dp keeps faces inclusive).
std::int64_t lattice_first(double min, double dp);
std::int64_t lattice_last(double max, double dp);

// Boundary particles of box walls: `layers` layers outward from the inner faces, offsets 0, dp, ...
void sample_walls(const BoxWalls& w, double dp, std::vector<Vec3>& out);
// A solid box: lattice points inside it, within `layers` * dp of its surface (all if layers <= 0).
void sample_solid(const SolidBox& b, double dp, std::vector<Vec3>& out);

// Points of a set, bucketed by cells of edge dp, answering "is any point closer than r?".
class PointHash {
public:
    PointHash(const std::vector<Vec3>& points, double cell);
    bool any_within(const Vec3& x, double r) const;

private:
    std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const;
    double cell_;
    std::vector<std::uint64_t> keys_;   // sorted cell keys, one per point
    std::vector<Vec3> points_;          // in key order
};

}  // namespace clsph::scene
