// Sampling geometry onto the dp lattice (points at integer multiples of dp on each axis), and the
// host-side spatial hash used to keep fluid at least dp from every boundary particle.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace clsph::scene {

// Lattice indices k with min <= k * dp <= max (a tolerance of 1e-9 dp keeps faces inclusive).
std::int64_t lattice_first(double min, double dp);
std::int64_t lattice_last(double max, double dp);

// A lattice point (multiples of dp, 21 bits per axis) as one sortable key: how a boundary particle
// is recognised as one of a solid's (ghost nodes, motion), in the scene's particles, a frame read
// back or a checkpoint alike.
inline std::uint64_t lattice_key(const Vec3& x, double dp) {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
        const auto i = static_cast<std::int64_t>(std::llround(x[a] / dp));
        k = (k << 21) | (static_cast<std::uint64_t>(i + (1 << 20)) & 0x1fffffu);
    }
    return k;
}

// The scene's particles sampled point by point on the host (boundaries in the scene's order, then
// fluid): meshes need it; for other scenes Scene::build_particles() takes the lattice plan, and
// the tests compare the two.
Particles sampled_particles(const Scene& scene);

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

// Fluid blocks by their xy footprints grown by `pad`, bucketed on a grid: the blocks whose grown
// footprint may hold a point (x, y), in increasing block index, without visiting every block, so
// that building a scene of many blocks stays near-linear in blocks and particles.
class FootprintIndex {
public:
    FootprintIndex(const std::vector<FluidBlock>& blocks, double pad);
    // Calls f(block) for the candidates in increasing order until f returns false.
    template <class F>
    void each_candidate(double x, double y, F&& f) const {
        if (starts_.empty()) return;
        const double fx = std::floor((x - origin_[0]) / cell_), fy = std::floor((y - origin_[1]) / cell_);
        if (!(fx >= 0 && fy >= 0 && fx < static_cast<double>(nx_) && fy < static_cast<double>(ny_))) return;
        const std::size_t c = static_cast<std::size_t>(fy) * nx_ + static_cast<std::size_t>(fx);
        for (std::size_t i = starts_[c]; i < starts_[c + 1]; ++i)
            if (!f(entries_[i])) return;
    }

private:
    double origin_[2] = {0, 0};
    double cell_ = 1;
    std::size_t nx_ = 0, ny_ = 0;
    std::vector<std::size_t> starts_;   // per cell, its first entry (CSR), plus the end
    std::vector<std::size_t> entries_;  // block indices, increasing within each cell
};

}  // namespace clsph::scene
