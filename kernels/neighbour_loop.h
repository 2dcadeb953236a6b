// The neighbour iteration every interaction kernel uses, written once. An interaction file defines
// what it needs from each neighbour and what it does with a pair, then includes this header, which
// defines the kernel INTERACTION_NAME in one of four schemes (-DCLSPH_LANES, -DCLSPH_CLUSTERS,
// -DCLSPH_COARSE):
//   fine   (default): a work-item per particle walks its cell's neighbour rows in global memory;
//   lanes (CPU form): a work-item per cell, its particles in vector lanes (-DCLSPH_LANES=8|16);
//   clusters        : as fine, the candidates from the cluster-pair lists of clusters.cl
//                     (-DCLSPH_CLUSTERS=4|8 particles a cluster, -DCLSPH_MASK_BITS=32|64);
//   coarse          : a work-group per cell stages each neighbour row in local memory in tiles of
//                     WG particles, and each work-item computes one particle of the cell.
//
// The interaction file defines, before including:
//   INTERACTION_NAME         kernel name
//   INTERACTION_ARGS         extra kernel parameters, starting with a comma
//   NEIGHBOUR_T              struct of what a pair needs from j; must have a float4 member `pos`
//   LOAD_NEIGHBOUR(nb, j)    statement filling NEIGHBOUR_T nb from the kernel's arrays except
//                            `pos`, which the loop loads itself (the fine scheme reads the rest
//                            only for candidates inside the support: most candidates are not)
//   STATE_T                  the per-particle accumulator
//   STATE_INIT(st, i, self)  statement (self is particle i's NEIGHBOUR_T)
//   PAIR(st, self, nb, i, j, rij, r2)   statement, for every j (i itself included) with r2 < support2;
//                            rij = x_j - x_i
//   STATE_STORE(st, i)       statement writing the result for particle i
// and may define (the fine and clusters schemes only; the others compute every particle):
//   SKIP_PARTICLE(self)      true for a particle i that needs no neighbour loop (index i in scope)
//   STORE_SKIPPED(i)         statement writing such a particle's result
// Particles [first, last) are computed; neighbours come from all of [0, n_active) (ghosts included).
#include "grid.h"

#if defined(CLSPH_LANES)

// lanes (the CPU form): a work-item per non-empty cell (launched with work-groups of one), the
// cell's particles CLSPH_LANES at a time in the lanes of vector types (lanes.h). Every lane is in
// the same cell, so a candidate's offset from the cell row is one scalar computation, its data are
// scalar loads, and only the distance and the pair terms are vectors. CPU OpenCL compilers do not
// vectorise the fine scheme (pocl: "loop control flow is not understood by vectorizer": each
// work-item's candidate loop has its own trip count), so they run it one particle at a time.
// The interaction file defines, besides the scalar interface above:
//   LANES_T                          the lanes' state (vectors of floatV / intV)
//   LANES_INIT(st, base, count)      statement: lanes l < count from particles base + l, the others
//                                    copies of the last (computed, never stored)
//   LANES_PAIR(st, j, rx, ry, rz, r2, hit)  statement: rij = x_j - x_i per lane, hit = r2 < support2
//   LANES_STORE(st, base, count)     statement
// Sums run over j in increasing order for every lane, as in the fine scheme.
#include "lanes.h"

__kernel void INTERACTION_NAME(const uint first, const uint last, const GridParams g, const float support2,
                               __global const float4* pos, __global const uint* cell_start,
                               __global const uint2* ranges INTERACTION_ARGS) {
    const uint c = get_global_id(0);
    const uint begin = max(cell_start[c], first), end = min(cell_start[c + 1u], last);
    if (begin >= end) return;
    const uint key_c = pos_key(pos[begin]);
    const int s_c = (int)key_s(g, key_c), a_c = (int)key_a(g, key_c);
    const uint b_c = key_b(g, key_c);
    for (uint base = begin; base < end; base += VW) {
        const uint count = min((uint)VW, end - base);
        floatV px, py, pz;
        {
            float tx[VW], ty[VW], tz[VW];
            for (uint l = 0; l < VW; ++l) {
                const float4 p = pos[base + min(l, count - 1u)];
                tx[l] = p.x;
                ty[l] = p.y;
                tz[l] = p.z;
            }
            px = vloadV(0, tx);
            py = vloadV(0, ty);
            pz = vloadV(0, tz);
        }
        LANES_T st;
        LANES_INIT(st, base, count);
        for (uint r = 0; r < ROWS; ++r) {
            const uint2 range = ranges[c * ROWS + r];
            if (range.x >= range.y) continue;
            const int ds = row_ds(r), da = row_da(r);
            int a2 = a_c + da;
            if (a2 < 0) a2 += (int)g.n_a;
            if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
            const uint centre = make_key(g, (uint)(s_c + ds), (uint)a2, b_c);
            float3 row_delta = (float3)(0.0f);
            COMP(row_delta, AXIS_S) = (float)ds * g.cell_s;
            COMP(row_delta, AXIS_A) = (float)da * g.cell_a;
            for (uint j = range.x; j < range.y; ++j) {
                const float4 pj = pos[j];
                float3 d = pj.xyz + row_delta;  // x_j relative to the centre of cell c
                COMP(d, AXIS_B) += (float)((int)(pos_key(pj) - centre)) * g.cell_b;
                const floatV rx = d.x - px, ry = d.y - py, rz = d.z - pz;
                const floatV r2 = rx * rx + ry * ry + rz * rz;
                const intV hit = r2 < support2;
                if (any(hit)) {
                    LANES_PAIR(st, j, rx, ry, rz, r2, hit);
                }
            }
        }
        LANES_STORE(st, base, count);
    }
}

#elif defined(CLSPH_CLUSTERS)

// clusters: a work-item per particle, as fine, but each row's candidates come from the cluster-pair
// list of the particle's cluster (clusters.cl): per row a bit mask over the row's clusters, whose
// set bits in increasing order give the clusters, each's particles in increasing order. The rows'
// listed particles are a superset of the pairs within the support, in the fine form's order, and
// each candidate is computed exactly as there: the sums are the fine form's, bit for bit. The
// particles of a cluster share its list, so the lanes of a cluster take the same branches up to
// the support test. A row with more clusters than a mask holds is tested whole.
#if CLSPH_MASK_BITS == 64
#define MASK_T ulong
#define MASK_LOW(m) (63u - (uint)clz((m) & (0ul - (m))))
#else
#define MASK_T uint
#define MASK_LOW(m) (31u - clz((m) & (0u - (m))))
#endif
#define CS CLSPH_CLUSTERS

// One candidate j of the row whose offset is row_offset (the fine form's body).
#define CLUSTER_CANDIDATE(j)                                                          \
    do {                                                                              \
        const float4 pj = pos[j];                                                     \
        float3 rij = pj.xyz + row_offset;                                             \
        COMP(rij, AXIS_B) += (float)((int)(pos_key(pj) - centre)) * g.cell_b;         \
        const float r2 = dot(rij, rij);                                               \
        if (r2 < support2) {                                                          \
            NEIGHBOUR_T nb;                                                           \
            nb.pos = pj;                                                              \
            LOAD_NEIGHBOUR(nb, j);                                                    \
            PAIR(st, self, nb, i, j, rij, r2);                                        \
        }                                                                             \
    } while (0)

__kernel void INTERACTION_NAME(const uint first, const uint last, const GridParams g, const float support2,
                               __global const float4* pos, __global const uint* cell_of,
                               __global const uint2* ranges, __global const uint* cell_start,
                               __global const uint* cluster_begin, __global const MASK_T* masks INTERACTION_ARGS) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    NEIGHBOUR_T self;
    self.pos = pos[i];
    LOAD_NEIGHBOUR(self, i);
#ifdef SKIP_PARTICLE
    if (SKIP_PARTICLE(self)) {
        STORE_SKIPPED(i);
        return;
    }
#endif
    const uint key_i = pos_key(self.pos);
    STATE_T st;
    STATE_INIT(st, i, self);
    const uint c = cell_of[i];
    const uint s = cell_start[c];
    const uint id = c + s / CS + (i - s) / CS;
    const int s_i = (int)key_s(g, key_i), a_i = (int)key_a(g, key_i);
    const uint b_i = key_b(g, key_i);
    for (uint r = 0; r < ROWS; ++r) {
        const uint2 range = ranges[c * ROWS + r];
        if (range.x >= range.y) continue;
        const int ds = row_ds(r), da = row_da(r);
        int a2 = a_i + da;
        if (a2 < 0) a2 += (int)g.n_a;
        if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
        const uint centre = make_key(g, (uint)(s_i + ds), (uint)a2, b_i);
        float3 row_offset = -self.pos.xyz;
        COMP(row_offset, AXIS_S) += (float)ds * g.cell_s;
        COMP(row_offset, AXIS_A) += (float)da * g.cell_a;
        const uint jc0 = cell_of[range.x] + range.x / CS;
        const uint count = cell_of[range.y - 1u] + 1u + range.y / CS - jc0;
        if (count > CLSPH_MASK_BITS) {
            for (uint j = range.x; j < range.y; ++j) CLUSTER_CANDIDATE(j);
            continue;
        }
        MASK_T m = masks[id * ROWS + r];
        while (m != 0) {
            const uint jc = jc0 + MASK_LOW(m);
            m &= m - (MASK_T)1;
            const uint jb = cluster_begin[jc], je = cluster_begin[jc + 1u];
            for (uint j = jb; j < je; ++j) CLUSTER_CANDIDATE(j);
        }
    }
    STATE_STORE(st, i);
}

#elif !defined(CLSPH_COARSE)

__kernel void INTERACTION_NAME(const uint first, const uint last, const GridParams g, const float support2,
                               __global const float4* pos, __global const uint* cell_of,
                               __global const uint2* ranges INTERACTION_ARGS) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    NEIGHBOUR_T self;
    self.pos = pos[i];
    LOAD_NEIGHBOUR(self, i);
#ifdef SKIP_PARTICLE
    if (SKIP_PARTICLE(self)) {
        STORE_SKIPPED(i);
        return;
    }
#endif
    const uint key_i = pos_key(self.pos);
    STATE_T st;
    STATE_INIT(st, i, self);
    const uint c = cell_of[i];
    // Within a neighbour row only the b cell can differ, by -1, 0 or +1, and the row's keys are
    // consecutive: key_j - key(row centre) is that difference. So each candidate costs one load,
    // an integer subtraction and a few flops; the s and a offsets are per row.
    const int s_i = (int)key_s(g, key_i), a_i = (int)key_a(g, key_i);
    const uint b_i = key_b(g, key_i);
    for (uint r = 0; r < ROWS; ++r) {
        const uint2 range = ranges[c * ROWS + r];
        if (range.x >= range.y) continue;
        const int ds = row_ds(r), da = row_da(r);
        int a2 = a_i + da;  // only rows inside the domain are non-empty; a may wrap
        if (a2 < 0) a2 += (int)g.n_a;
        if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
        const uint centre = make_key(g, (uint)(s_i + ds), (uint)a2, b_i);
        float3 row_offset = -self.pos.xyz;
        COMP(row_offset, AXIS_S) += (float)ds * g.cell_s;
        COMP(row_offset, AXIS_A) += (float)da * g.cell_a;
        // Unrolled by 4: H200 force pass 8.84 -> 8.37 ms (the pair terms of one candidate overlap
        // the next candidates' loads); the distance tests alone do not change (BENCHMARKS.md).
#pragma unroll 4
        for (uint j = range.x; j < range.y; ++j) {
            const float4 pj = pos[j];
            float3 rij = pj.xyz + row_offset;
            COMP(rij, AXIS_B) += (float)((int)(pos_key(pj) - centre)) * g.cell_b;
            const float r2 = dot(rij, rij);
            if (r2 < support2) {
                NEIGHBOUR_T nb;
                nb.pos = pj;
                LOAD_NEIGHBOUR(nb, j);
                PAIR(st, self, nb, i, j, rij, r2);
            }
        }
    }
    STATE_STORE(st, i);
}

#else  // coarse-grained: one work-group per non-empty cell

#ifndef WG
#define WG 64
#endif

__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void INTERACTION_NAME(
    const uint first, const uint last, const GridParams g, const float support2, __global const float4* pos,
    __global const uint* cell_start, __global const uint2* ranges INTERACTION_ARGS) {
    __local NEIGHBOUR_T tile[WG];
    const uint c = get_group_id(0);
    const uint lid = get_local_id(0);
    // The cell's particles, clipped to the computed range (ghost cells are not computed).
    const uint cell_begin = max(cell_start[c], first), cell_end = min(cell_start[c + 1u], last);
    if (cell_begin >= cell_end) return;  // whole group leaves together: no barrier is skipped
    for (uint base = cell_begin; base < cell_end; base += WG) {
        const uint i = base + lid;
        const bool active = i < cell_end;
        NEIGHBOUR_T self;
        STATE_T st;
        uint key_i = 0;
        if (active) {
            self.pos = pos[i];
            LOAD_NEIGHBOUR(self, i);
            key_i = pos_key(self.pos);
            STATE_INIT(st, i, self);
        }
        for (uint r = 0; r < ROWS; ++r) {
            const uint2 range = ranges[c * ROWS + r];
            for (uint tile_begin = range.x; tile_begin < range.y; tile_begin += WG) {
                const uint count = min((uint)WG, range.y - tile_begin);
                barrier(CLK_LOCAL_MEM_FENCE);
                if (lid < count) {
                    NEIGHBOUR_T nb;
                    nb.pos = pos[tile_begin + lid];
                    LOAD_NEIGHBOUR(nb, tile_begin + lid);
                    tile[lid] = nb;
                }
                barrier(CLK_LOCAL_MEM_FENCE);
                if (active) {
                    for (uint t = 0; t < count; ++t) {
                        const NEIGHBOUR_T nb = tile[t];
                        const uint j = tile_begin + t;
                        const float3 rij = relative_position(g, key_i, self.pos, pos_key(nb.pos), nb.pos);
                        const float r2 = dot(rij, rij);
                        if (r2 < support2) {
                            PAIR(st, self, nb, i, j, rij, r2);
                        }
                    }
                }
            }
        }
        if (active) {
            STATE_STORE(st, i);
        }
    }
}

#endif
