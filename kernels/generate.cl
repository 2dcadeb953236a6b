// Set-up on the device: the particles of one lattice piece (a box's walls, a solid box, a fluid
// block) in this device's slab, from per-axis tables the host computed
// (host/src/scene/lattice_plan.hpp, host/src/device/generate.cpp). A point is (i0, i1, i2): its
// coordinate indices along the piece's loop positions (0: the split axis, whose coordinates are
// "planes"). Nothing here is floating-point arithmetic: positions, densities and the removal of
// fluid near boundaries come from the tables, so every device writes exactly the host's particles.
#include "shared.h"

#define GEN_OUTSIDE 0xffffffffu

// The stored position: the offsets from the cell centre (xyz) and the cell key (w), as
// Grid::locate gives them; a point outside the domain gets the invalid key and no offset.
inline float4 gen_position(const uint i0, const uint i1, const uint i2, __global const uint* part0,
                           __global const uint* part1, __global const uint* part2, __global const float* off0,
                           __global const float* off1, __global const float* off2, const uint c0, const uint c1,
                           const uint c2, const uint invalid_key) {
    const uint k0 = part0[i0], k1 = part1[i1], k2 = part2[i2];
    float o[3] = {0.0f, 0.0f, 0.0f};
    uint key = invalid_key;
    if (k0 != GEN_OUTSIDE && k1 != GEN_OUTSIDE && k2 != GEN_OUTSIDE) {
        key = k0 | k1 | k2;
        o[c0] = off0[i0];
        o[c1] = off1[i1];
        o[c2] = off2[i2];
    }
    return (float4)(o[0], o[1], o[2], as_float(key));
}

// The first set bit of the three masks together (the block whose pressure or velocity the point
// takes), or `none`.
inline uint gen_block(const uint i0, const uint i1, const uint i2, __global const ulong* mask0,
                      __global const ulong* mask1, __global const ulong* mask2, const uint none) {
    const ulong m = mask0[i0] & mask1[i1] & mask2[i2];
    if (m == 0) return none;
    return (uint)popcount((m & (~m + 1ul)) - 1ul);
}

inline uint gen_pick(const uint pos, const uint i0, const uint i1, const uint i2) {
    return pos == 0u ? i0 : pos == 1u ? i1 : i2;
}

#define GEN_AXIS_ARGS                                                                                      \
    __global const uint *part0, __global const uint *part1, __global const uint *part2,                  \
        __global const float *off0, __global const float *off1, __global const float *off2, const uint c0, \
        const uint c1, const uint c2, const uint invalid_key, __global const ulong *mask0,                \
        __global const ulong *mask1, __global const ulong *mask2, const uint none,                       \
        __global const float *density, const uint nz, const uint posz
#define GEN_AXIS_PASS part0, part1, part2, off0, off1, off2, c0, c1, c2, invalid_key

// Boundary pieces: one work-item per particle. Particle r of the slab's points of this piece lies
// in the last plane whose start is <= r; within a plane every point is kept when the plane is a
// layer, otherwise the rows that are layers hold n2 points and the others the l2 layer columns.
__kernel void generate_boundary(const uint n, const uint out_first, const uint id_first, const uint planes,
                                const uint plane_first, __global const uint* plane_start, const uint n1,
                                const uint n2, const uint l2, __global const uchar* layer0,
                                __global const uint* layer1_before, __global const uint* layer2_at, GEN_AXIS_ARGS,
                                __global float4* pos, __global float4* velrho, __global float4* accel,
                                __global uint* ids) {
    const uint r = (uint)get_global_id(0);
    if (r >= n) return;
    uint lo = 0, hi = planes;  // plane_start[lo] <= r < plane_start[hi]
    while (hi - lo > 1u) {
        const uint mid = lo + (hi - lo) / 2u;
        if (plane_start[mid] <= r) lo = mid;
        else hi = mid;
    }
    const uint i0 = plane_first + lo;
    const uint rr = r - plane_start[lo];
    uint i1, i2;
    if (layer0[i0]) {
        i1 = rr / n2;
        i2 = rr % n2;
    } else {
        uint a = 0, b = n1;  // rows: R(j) = L(j) n2 + (j - L(j)) l2, L(j) layer rows before j
        while (b - a > 1u) {
            const uint m = a + (b - a) / 2u;
            const uint lm = layer1_before[m];
            if (lm * n2 + (m - lm) * l2 <= rr) a = m;
            else b = m;
        }
        const uint la = layer1_before[a];
        const uint w = rr - (la * n2 + (a - la) * l2);
        i1 = a;
        i2 = layer1_before[a + 1] != la ? w : layer2_at[w];
    }
    const uint slot = out_first + r;
    pos[slot] = gen_position(i0, i1, i2, GEN_AXIS_PASS);
    const uint row = gen_block(i0, i1, i2, mask0, mask1, mask2, none);
    velrho[slot] = (float4)(0.0f, 0.0f, 0.0f, density[row * nz + gen_pick(posz, i0, i1, i2)]);
    accel[slot] = (float4)(0.0f);
    ids[slot] = (id_first + r) | (CLSPH_TYPE_BOUNDARY << CLSPH_TYPE_SHIFT);
}

// Fluid pieces, candidate c of a chunk: the point (i0, i1, i2) of the slab's planes.
inline void gen_candidate(const uint c, const uint plane_first, const uint n1, const uint n2, uint* i0, uint* i1,
                          uint* i2) {
    const uint per_plane = n1 * n2;
    *i0 = plane_first + c / per_plane;
    const uint rem = c % per_plane;
    *i1 = rem / n2;
    *i2 = rem % n2;
}

// Kept (1) unless within dp of a boundary piece: for some table t and axis a,
// layer[a] + any[b] + any[c] < limit (fixed-point squared distances; tables [t][axis][index] with
// axis blocks of n0, n1, n2).
__kernel void generate_fluid_flags(const uint n, const uint first, const uint plane_first, const uint n0,
                                   const uint n1, const uint n2, const uint tables, __global const long* layer,
                                   __global const long* any, const long limit, __global uint* flags) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    uint i0, i1, i2;
    gen_candidate(first + g, plane_first, n1, n2, &i0, &i1, &i2);
    const uint stride = n0 + n1 + n2;
    uint keep = 1u;
    for (uint t = 0; t < tables && keep; ++t) {
        const uint b = t * stride;
        const long l0 = layer[b + i0], l1 = layer[b + n0 + i1], l2 = layer[b + n0 + n1 + i2];
        const long a0 = any[b + i0], a1 = any[b + n0 + i1], a2 = any[b + n0 + n1 + i2];
        if (l0 + a1 + a2 < limit || l1 + a2 + a0 < limit || l2 + a0 + a1 < limit) keep = 0u;
    }
    flags[g] = keep;
}

// The kept candidates of a chunk at their scanned places; `written` kept before this chunk.
__kernel void generate_fluid_write(const uint n, const uint first, const uint plane_first, const uint n1,
                                   const uint n2, const uint out_first, const uint id_first, const uint written,
                                   __global const uint* flags, __global const uint* rank,
                                   __global const float4* velocity, GEN_AXIS_ARGS, __global float4* pos,
                                   __global float4* velrho, __global float4* accel, __global uint* ids) {
    const uint g = (uint)get_global_id(0);
    if (g >= n || flags[g] == 0u) return;
    uint i0, i1, i2;
    gen_candidate(first + g, plane_first, n1, n2, &i0, &i1, &i2);
    const uint k = written + rank[g];
    const uint slot = out_first + k;
    pos[slot] = gen_position(i0, i1, i2, GEN_AXIS_PASS);
    const uint row = gen_block(i0, i1, i2, mask0, mask1, mask2, none);
    const float4 v = velocity[row];
    velrho[slot] = (float4)(v.x, v.y, v.z, density[row * nz + gen_pick(posz, i0, i1, i2)]);
    accel[slot] = (float4)(0.0f);
    ids[slot] = (id_first + k) | (CLSPH_TYPE_FLUID << CLSPH_TYPE_SHIFT);
}
