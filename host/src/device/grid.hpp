// The uniform cell grid of one simulation: which axis is split between devices, how many cells
// each axis has, how a cell becomes a 32-bit key, and how a position in double becomes a
// (cell, float offset from the cell centre) pair. Pure C++: no OpenCL here.
//
// Why cell-relative positions: a float absolute coordinate at x = 10 m has a resolution of ~1e-6 m,
// so a particle moving 1e-8 m per step would never move. Offsets from the cell centre stay below
// half a cell (a few mm), where float resolution is ~1e-10 m; the integer cell carries the rest.
#pragma once
#include "shared.h"

#include <array>
#include <cstdint>
#include <string>

namespace clsph::device {

struct Box {
    std::array<double, 3> lo{0, 0, 0}, hi{1, 1, 1};
};

class Grid {
public:
    // support: the kernel's support radius (cell edges are at least this). split_axis -1 picks the
    // longest axis. periodic[k] makes axis k wrap; only one non-split axis may be periodic, its
    // extent must hold at least 3 cells, and its cells are stretched to divide it exactly.
    // Throws SceneError when the domain needs more cells than 32-bit keys can name.
    // reach: cells along the a and b axes are support / reach (1 or 2; s keeps whole supports), so
    // the neighbour rows cover less volume around a particle (reach 2: 150 support^3/8 instead of 216).
    Grid(const Box& domain, double support, int split_axis = -1, std::array<bool, 3> periodic = {false, false, false},
         int reach = 1);

    const GridParams& params() const { return p_; }
    const Box& domain() const { return domain_; }
    const std::array<bool, 3>& periodic() const { return periodic_; }
    // Axis (0 = x, 1 = y, 2 = z) of key position 0 = s, 1 = a, 2 = b.
    int axis(int key_position) const { return axis_[key_position]; }
    std::array<int, 3> axes() const { return axis_; }
    unsigned key_bits() const { return key_bits_; }
    int reach() const { return reach_; }
    // Neighbour rows per cell (the cell tables hold this many ranges per cell): 3 (2 reach + 1).
    std::size_t rows() const { return 3 * static_cast<std::size_t>(2 * reach_ + 1); }
    std::uint64_t cell_count() const;
    std::array<double, 3> cell_size_xyz() const;
    bool periodic(int xyz) const { return periodic_[xyz]; }

    // Cell coordinates (s, a, b) <-> key.
    std::uint32_t key(std::uint32_t s, std::uint32_t a, std::uint32_t b) const;
    std::array<std::uint32_t, 3> cell_of_key(std::uint32_t key) const;

    // A position (xyz, double) as cell key + offset from the cell centre (xyz, float). Positions
    // outside the domain (after periodic wrap) give invalid_key.
    // One axis of locate(): the cell index along key position `pos` (of axis axis(pos)) and the
    // offset from that cell's centre; false when the coordinate is outside the domain. locate()
    // is the three axes together, so a per-axis table reproduces its keys and offsets exactly.
    bool locate_axis(int pos, double x, std::uint32_t& cell, float& offset) const;
    // A key is the OR of its three positions' parts (key(s, a, b) == part(0, s) | part(1, a) | part(2, b)).
    std::uint32_t key_part(int pos, std::uint32_t cell) const;
    std::uint32_t locate(const std::array<double, 3>& x, std::array<float, 3>& offset) const;
    // Back to an absolute position (double).
    std::array<double, 3> position(std::uint32_t key, const std::array<float, 3>& offset) const;

    // -D options telling kernels which xyz component each key axis is.
    std::string kernel_options() const;

private:
    Box domain_;
    GridParams p_{};
    std::array<int, 3> axis_{0, 1, 2};
    std::array<bool, 3> periodic_{false, false, false};
    unsigned key_bits_ = 0;
    int reach_ = 1;
};

// The reach a scene's grid should have: 2 where cells of support x support/2 x support/2 still hold
// enough particles to fill a warp's worth of work (support >= 3.5 dp, 10+ per cell), else 1.
// Measured on SPHERIC-2 (hdp 2, support 4 dp; BENCHMARKS.md).
int reach_for(double support, double dp);

}  // namespace clsph::device
