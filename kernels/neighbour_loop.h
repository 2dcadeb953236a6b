// The neighbour iteration every interaction kernel uses, written once. An interaction file defines
// what it needs from each neighbour and what it does with a pair, then includes this header, which
// defines the kernel INTERACTION_NAME in one of five schemes (-DCLSPH_MASKED, -DCLSPH_TILED, -DCLSPH_LANES, -DCLSPH_COARSE):
//   fine   (default): a work-item per particle walks its cell's neighbour rows in global memory;
//   masked          : as fine, distances of 32 candidates first, then the pairs of the hits only;
//   tiled           : 32 particles of a cell per work-group, candidates in local memory, the hits
//                     of all work-items shared out evenly before the pair terms (-DCLSPH_TILED);
//   lanes (CPU form): a work-item per cell, its particles in vector lanes (-DCLSPH_LANES=8|16);
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
// Particles [first, last) are computed; neighbours come from all of [0, n_active) (ghosts included).
#include "grid.h"

#if defined(CLSPH_MASKED)

// masked: a work-item per particle, as fine, but each neighbour row is taken in batches of 32
// candidates: first only the distances, into a bit mask, then the pair terms for the set bits alone.
// On a GPU the lanes of a warp walk the same candidates (they sit in one cell), and in the fine
// scheme the whole warp runs the pair arithmetic whenever any lane has a hit (with cells of edge 2h
// about 16 % of candidates hit, but almost every candidate hits some lane of 32); here it runs it as
// often as the lane with the most hits in the batch. Hits are taken lowest bit first: the sum runs
// over j in increasing order, the same order as fine.
#ifndef CLSPH_BATCH
#define CLSPH_BATCH 32
#endif

__kernel void INTERACTION_NAME(const uint first, const uint last, const GridParams g, const float support2,
                               __global const float4* pos, __global const uint* cell_of,
                               __global const uint2* ranges INTERACTION_ARGS) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    NEIGHBOUR_T self;
    self.pos = pos[i];
    LOAD_NEIGHBOUR(self, i);
    const uint key_i = pos_key(self.pos);
    STATE_T st;
    STATE_INIT(st, i, self);
    const uint c = cell_of[i];
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
        const uint row_last = range.y - 1u;
        for (uint base = range.x; base < range.y; base += CLSPH_BATCH) {
#if CLSPH_BATCH == 64
            ulong mask = 0;
#else
            uint mask = 0;
#endif
            // A fixed trip count, so the compiler unrolls it; candidates past the row's end load
            // its last particle (always valid) and never set their bit.
            for (uint t = 0; t < CLSPH_BATCH; ++t) {
                const uint j = min(base + t, row_last);
                const float4 pj = pos[j];
                float3 rij = pj.xyz + row_offset;
                COMP(rij, AXIS_B) += (float)((int)(pos_key(pj) - centre)) * g.cell_b;
                const float r2 = dot(rij, rij);
#if CLSPH_BATCH == 64
                mask |= (ulong)(r2 < support2 && base + t < range.y) << t;
#else
                mask |= (uint)(r2 < support2 && base + t < range.y) << t;
#endif
            }
            while (mask != 0) {
                const uint t = (uint)(8 * sizeof(mask) - 1) - (uint)clz(mask & (~mask + 1));  // lowest set bit
                mask &= mask - 1;
                const uint j = base + t;
                NEIGHBOUR_T nb;
                nb.pos = pos[j];
                float3 rij = nb.pos.xyz + row_offset;
                COMP(rij, AXIS_B) += (float)((int)(pos_key(nb.pos) - centre)) * g.cell_b;
                const float r2 = dot(rij, rij);
                LOAD_NEIGHBOUR(nb, j);
                PAIR(st, self, nb, i, j, rij, r2);
            }
        }
    }
    STATE_STORE(st, i);
}

#elif defined(CLSPH_TILED)

// tiled: a work-group of 32 work-items per chunk of at most 32 particles of one cell (chunk_start[c]:
// the first chunk of cell c, an exclusive scan of ceil(owned particles / 32) over the cells). Each
// neighbour row is staged 32 candidates at a time in local memory, relative to the cell's centre;
// every work-item tests its particle against the 32 into a bit mask; then the hits of all work-items
// are dealt out evenly (hit p of the group to work-item p mod 32), each one's terms written to local
// memory in hit order, and each work-item adds its own particle's terms in candidate order. So the
// pair arithmetic runs on nearly every lane (the fine scheme runs it on a third: a warp runs it at
// every candidate some lane hits), and the sum order is the fine scheme's.
// The interaction file defines, besides the scalar interface: TERMS(self, nb, rij, r2), a float4 of
// the pair's terms, and STATE_ADD(st, terms); PAIR must be STATE_ADD(st, TERMS(...)).
#ifndef TERMS
#error "the tiled scheme needs TERMS and STATE_ADD"
#endif
#define TILE 32u
#ifndef SLOTS
#define SLOTS 128u
#endif

inline uint nth_set_bit(uint m, uint k) {  // position of the k-th (0-based) set bit of m
    uint at = 0;
    for (uint w = 16u; w > 0u; w >>= 1) {
        const uint low = popcount(m & ((1u << w) - 1u));
        if (k >= low) {
            k -= low;
            m >>= w;
            at += w;
        }
    }
    return at;
}

__kernel __attribute__((reqd_work_group_size(32, 1, 1))) void INTERACTION_NAME(
    const uint first, const uint last, const GridParams g, const float support2, __global const float4* pos,
    __global const uint* cell_start, __global const uint2* ranges INTERACTION_ARGS, __global const uint* chunk_start,
    const uint cells) {
    __local float4 tile_rel[TILE];  // candidate positions relative to the centre of the cell
    __local NEIGHBOUR_T tile[TILE];
    __local NEIGHBOUR_T selves[TILE];
    __local float4 self_rel[TILE];
    __local uint masks[TILE];
    __local uint offsets[TILE + 1u];
    __local float4 terms[SLOTS];
    const uint lid = get_local_id(0), group = get_group_id(0);
    if (group >= chunk_start[cells]) return;  // the launch is an upper bound; the whole group leaves
    uint lo = 0, hi = cells;                   // the cell: the last c with chunk_start[c] <= group
    while (hi - lo > 1u) {
        const uint mid = (lo + hi) >> 1;
        if (chunk_start[mid] <= group) lo = mid; else hi = mid;
    }
    const uint c = lo;
    const uint cell_begin = max(cell_start[c], first), cell_end = min(cell_start[c + 1u], last);
    const uint i = cell_begin + (group - chunk_start[c]) * TILE + lid;
    const bool active = i < cell_end;
    const uint key_c = pos_key(pos[cell_begin]);
    const int s_c = (int)key_s(g, key_c), a_c = (int)key_a(g, key_c);
    const uint b_c = key_b(g, key_c);
    NEIGHBOUR_T self;
    self.pos = pos[active ? i : cell_begin];
    LOAD_NEIGHBOUR(self, active ? i : cell_begin);
    selves[lid] = self;
    self_rel[lid] = (float4)(self.pos.xyz, 0.0f);
    STATE_T st;
    STATE_INIT(st, i, self);
    for (uint r = 0; r < ROWS; ++r) {
        const uint2 range = ranges[c * ROWS + r];
        const int ds = row_ds(r), da = row_da(r);
        int a2 = a_c + da;
        if (a2 < 0) a2 += (int)g.n_a;
        if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
        const uint centre = make_key(g, (uint)(s_c + ds), (uint)a2, b_c);
        float3 row_delta = (float3)(0.0f);
        COMP(row_delta, AXIS_S) = (float)ds * g.cell_s;
        COMP(row_delta, AXIS_A) = (float)da * g.cell_a;
        for (uint base = range.x; base < range.y; base += TILE) {
            const uint count = min(TILE, range.y - base);
            barrier(CLK_LOCAL_MEM_FENCE);
            if (lid < count) {
                NEIGHBOUR_T nb;
                nb.pos = pos[base + lid];
                LOAD_NEIGHBOUR(nb, base + lid);
                float3 d = nb.pos.xyz + row_delta;
                COMP(d, AXIS_B) += (float)((int)(pos_key(nb.pos) - centre)) * g.cell_b;
                tile_rel[lid] = (float4)(d, 0.0f);
                tile[lid] = nb;
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            uint mask = 0u;
            for (uint t = 0; t < TILE; ++t) {
                const float3 rij = tile_rel[t].xyz - self.pos.xyz;
                mask |= (uint)(dot(rij, rij) < support2 && t < count) << t;
            }
            if (!active) mask = 0u;
            masks[lid] = mask;
            offsets[lid + 1u] = popcount(mask);
            barrier(CLK_LOCAL_MEM_FENCE);
            if (lid == 0u) {  // exclusive prefix of the hit counts (32 adds)
                offsets[0] = 0u;
                for (uint l = 1u; l <= TILE; ++l) offsets[l] += offsets[l - 1u];
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            const uint total = offsets[TILE];
            const uint mine = offsets[lid], mine_end = offsets[lid + 1u];
            for (uint round = 0; round < total; round += SLOTS) {
                const uint round_end = min(total, round + SLOTS);
                for (uint p = round + lid; p < round_end; p += TILE) {
                    uint o_lo = 0, o_hi = TILE;  // the work-item that owns hit p
                    while (o_hi - o_lo > 1u) {
                        const uint mid = (o_lo + o_hi) >> 1;
                        if (offsets[mid] <= p) o_lo = mid; else o_hi = mid;
                    }
                    const uint t = nth_set_bit(masks[o_lo], p - offsets[o_lo]);
                    const NEIGHBOUR_T si = selves[o_lo], nj = tile[t];
                    const float3 rij = tile_rel[t].xyz - self_rel[o_lo].xyz;
                    terms[p - round] = TERMS(si, nj, rij, dot(rij, rij));
                }
                barrier(CLK_LOCAL_MEM_FENCE);
                for (uint q = max(mine, round); q < min(mine_end, round_end); ++q) STATE_ADD(st, terms[q - round]);
                barrier(CLK_LOCAL_MEM_FENCE);
            }
        }
    }
    if (active) {
        STATE_STORE(st, i);
    }
}

#elif defined(CLSPH_LANES)

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

#elif !defined(CLSPH_COARSE)

__kernel void INTERACTION_NAME(const uint first, const uint last, const GridParams g, const float support2,
                               __global const float4* pos, __global const uint* cell_of,
                               __global const uint2* ranges INTERACTION_ARGS) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    NEIGHBOUR_T self;
    self.pos = pos[i];
    LOAD_NEIGHBOUR(self, i);
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
