// Where the particles go: the domain's cell columns along the split axis, cut into one slab per
// device. Column keys, the owner of a key, the columns each slab needs (its own and one halo
// column either side), the host-side census of the scene that the first cuts and the calibration
// start from, the first upload's split, and the column profile the balancer reads every step.
#pragma once
#include "balance/balancer.hpp"
#include "clsph/particles.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "multi/slab.hpp"
#include "scene/lattice_plan.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::multi {

// The columns a device needs: [lo, hi) = its own [first, end) and one column either side (the
// support radius is one column), or two with laminar+sps (the stress of a ghost one column out
// is computed where it is held, from its own neighbours). An empty device needs nothing.
struct Need {
    std::size_t lo = 0, first = 0, end = 0, hi = 0;
    bool empty() const { return hi <= lo; }
};

// The scene's particles on the host, before the first step.
struct Census {
    std::vector<std::uint32_t> key;           // per particle (invalid outside the domain)
    balance::ColumnProfile profile;           // work and particles per column
    std::vector<std::size_t> boundary;        // boundary particles per column (they never move)
};

class Partition {
public:
    explicit Partition(const device::Grid& grid) : grid_(grid) {}
    const device::Grid& grid() const { return grid_; }
    std::size_t columns() const { return grid_.params().n_s; }
    // The first key of a column (the invalid key past the last column).
    std::uint32_t column_key(std::size_t column) const;
    std::size_t column_of(std::uint32_t key) const { return grid_.cell_of_key(key)[0]; }
    device::KeyRange keys_of(const Need& need) const;

    std::vector<Need> needs(const std::vector<Slab>& slabs) const;
    void set_halo(std::size_t columns) { halo_ = columns; }  // 1, or 2 with laminar+sps or summation density
    std::size_t owner_of(std::uint32_t key, const std::vector<Slab>& slabs) const;
    static std::vector<std::size_t> cuts(const std::vector<Slab>& slabs);
    // Checks `cuts` (devices + 1 non-decreasing columns from 0 to the column count) and sets them;
    // a cut where restrict_cuts() forbids one moves to the nearest column where it may go.
    void set_cuts(std::vector<Slab>& slabs, const std::vector<std::size_t>& cuts) const;
    // mDBC: a boundary particle's ghost node (particle + offset) interpolates from the fluid within
    // a support of it, which may lie two columns from the particle's; its owner holds only one halo
    // column either side. Cuts are forbidden where a slab would then lack a column one of its
    // boundary particles needs (the balancer is told through ColumnProfile::cut_allowed).
    void restrict_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets, double support);
    // The same for particles that move where no one knows ahead (floating bodies), every step from
    // where they are now, with a margin of columns they may move by before their mDBC pass: the
    // cuts allowed are then those both this and restrict_cuts() allow.
    void restrict_body_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets, double support,
                            std::size_t margin);
    const std::vector<char>& cut_allowed() const { return cut_allowed_; }

    Census census(const Particles& p);
    // The same from a plan's per-plane counts, without the particles (no keys).
    Census census(const scene::LatticePlan& plan);
    // Each slab's particles for the first upload; particles outside the domain go to the first,
    // whose first sort removes and counts them.
    std::vector<Particles> split(const Particles& p, const Census& census, const std::vector<Slab>& slabs) const;
    // Particles per column now, from each slab's column positions, weighted by type (boundary
    // particles, counted once, cost less).
    balance::ColumnProfile column_profile(const std::vector<Slab>& slabs) const;

private:
    const device::Grid& grid_;
    std::vector<std::size_t> boundary_per_column_;
    std::vector<char> cut_allowed_;    // empty: anywhere
    std::vector<char> fixed_allowed_;  // restrict_cuts()'s (empty: anywhere)
    std::vector<char> allowed_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets,
                                   double support, std::size_t margin) const;
    std::size_t halo_ = 1;
};

}  // namespace clsph::multi
