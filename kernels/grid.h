// Grid helpers for kernels: key fields, axis mapping (AXIS_S/A/B given as -D), and the relative
// position of two particles from their cells and cell-centre offsets.
#ifndef CLSPH_GRID_H
#define CLSPH_GRID_H
#include "shared.h"

#ifndef AXIS_S
#define AXIS_S 0
#define AXIS_A 1
#define AXIS_B 2
#endif

// Component of a float4/float3 by xyz axis number known at compile time.
#define COMP_0(v) ((v).x)
#define COMP_1(v) ((v).y)
#define COMP_2(v) ((v).z)
#define COMP_(v, k) COMP_##k(v)
#define COMP(v, k) COMP_(v, k)
#define S_OF(v) COMP(v, AXIS_S)
#define A_OF(v) COMP(v, AXIS_A)
#define B_OF(v) COMP(v, AXIS_B)

// Cells along the a and b axes may be a fraction 1/CLSPH_REACH of the support (the host's
// Grid::reach(), given as -D): a particle's neighbours then lie within CLSPH_REACH cells along a and
// b (one along s, whose cells stay a whole support: slabs and halos are whole columns). A cell's
// neighbour rows are (s + ds, a + da) for ds in -1..1 and da in -REACH..REACH, each the cells
// b - REACH .. b + REACH: consecutive keys, since b is padded by REACH empty cells at each end.
#ifndef CLSPH_REACH
#define CLSPH_REACH 1
#endif
#define ROWS_A (2u * CLSPH_REACH + 1u)
#define ROWS (3u * ROWS_A)
inline int row_ds(const uint r) { return (int)(r / ROWS_A) - 1; }
inline int row_da(const uint r) { return (int)(r % ROWS_A) - CLSPH_REACH; }

inline uint key_s(const GridParams g, uint key) { return g.shift_s >= 32u ? 0u : key >> g.shift_s; }
inline uint key_a(const GridParams g, uint key) { return (key >> g.shift_a) & g.mask_a; }
inline uint key_b(const GridParams g, uint key) { return (key & g.mask_b) - CLSPH_REACH; }
inline uint make_key(const GridParams g, uint s, uint a, uint b) {
    return (g.shift_s >= 32u ? 0u : (s << g.shift_s)) | (a << g.shift_a) | (b + CLSPH_REACH);
}

// First index in sorted keys[0..n) whose key is >= want (cell tables, slab edges, probes).
inline uint lower_bound_key(__global const uint* keys, const uint n, const uint want) {
    uint lo = 0, hi = n;
    while (lo < hi) {
        const uint mid = (lo + hi) >> 1;
        if (keys[mid] < want) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

// Particles [*begin, *end) of neighbour row r around the cell (s, a, b) of an arbitrary point (a
// probe, a ghost node), found in the cell tables (`cells` non-empty cells) by binary search;
// false when the row lies outside the domain. Axis a wraps where periodic.
inline bool row_of_point(const GridParams g, const uint cells, __global const uint* cell_key,
                         __global const uint* cell_start, const int s, const int a, const uint b, const uint r,
                         uint* begin, uint* end) {
    const int s2 = s + row_ds(r);
    int a2 = a + row_da(r);
    if (g.periodic_a) {
        if (a2 < 0) a2 += (int)g.n_a;
        if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
    }
    if (s2 < 0 || s2 >= (int)g.n_s || a2 < 0 || a2 >= (int)g.n_a) return false;
    const uint mid = make_key(g, (uint)s2, (uint)a2, b);
    *begin = cell_start[lower_bound_key(cell_key, cells, mid - CLSPH_REACH)];
    *end = cell_start[lower_bound_key(cell_key, cells, mid + CLSPH_REACH + 1u)];
    return true;
}

// The key of a particle is kept in pos.w (as bits), next to its offset from the cell centre.
inline uint pos_key(const float4 p) { return as_uint(p.w); }

// Vector from particle i to particle j (x_j - x_i) given both keys and offsets. Cell differences
// are small integers (neighbours are at most one cell apart, or wrap on a periodic axis), so the
// result is exact to float resolution of the offsets, wherever the particles are in the domain.
inline float3 relative_position(const GridParams g, const uint key_i, const float4 pi, const uint key_j,
                                const float4 pj) {
    int ds = (int)key_s(g, key_j) - (int)key_s(g, key_i);
    int da = (int)key_a(g, key_j) - (int)key_a(g, key_i);
    const int db = (int)key_b(g, key_j) - (int)key_b(g, key_i);
    if (g.periodic_a) {  // minimum image across the wrap
        if (da > CLSPH_REACH) da -= (int)g.n_a;
        if (da < -CLSPH_REACH) da += (int)g.n_a;
    }
    float3 cell_delta;
    COMP(cell_delta, AXIS_S) = (float)ds * g.cell_s;
    COMP(cell_delta, AXIS_A) = (float)da * g.cell_a;
    COMP(cell_delta, AXIS_B) = (float)db * g.cell_b;
    return cell_delta + (pj.xyz - pi.xyz);
}

#endif
