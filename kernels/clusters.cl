// The cluster-pair lists of the clusters interaction form (neighbour_loop.h, -DCLSPH_CLUSTERS),
// built on the device before every interaction pass (host/src/device/cluster_list.cpp).
//
// A cluster is up to CS = CLSPH_CLUSTERS consecutive sorted particles of one cell: cell c of
// particles [s, e) holds ceil((e - s) / CS) of them, the k-th [s + k CS, min(s + (k + 1) CS, e)).
// Its index is id(c, k) = c + floor(s / CS) + k: increasing in (c, k), unique, and between two
// cells at most one index unused (a gap), so indices stay below cells + n / CS + 1 without a scan.
// begin[id] is the cluster's first particle; a gap's is its cell's end, so that the cluster of id
// is always [begin[id], begin[id + 1]) (a gap: empty).
//
// The list of an i-cluster: for each of its cell's neighbour rows, a bit mask over the row's
// cluster indices (bit t: index jc0 + t, jc0 the index of the row's first cluster), set where the
// two clusters' bounding boxes come within the support (with a margin for round-off: a bit may be
// set needlessly, never missing). A row of more than CLSPH_MASK_BITS indices has no mask: the
// interaction pass tests the whole row there, as the fine form does.
#include "grid.h"

#ifndef CLSPH_CLUSTERS
#define CLSPH_CLUSTERS 4
#endif
#define CS CLSPH_CLUSTERS
#if CLSPH_MASK_BITS == 64
#define MASK_T ulong
#else
#define MASK_T uint
#endif

// Each cell's clusters: their first particles and bounding boxes (offsets from the cell centre; w
// unused), and the gap after them; the last cell also the end sentinel. Launched over the cells
// the tables hold (`cells`: the count, or the capacity of the step ahead, whose cells beyond the
// count are empty); `cap` indices are allocated.
__kernel void cluster_boxes(const uint cells, const uint cap, __global const uint* cell_start,
                            __global const float4* pos, __global uint* begin, __global float4* boxes) {
    const uint c = get_global_id(0);
    if (c >= cells) return;
    const uint s = cell_start[c], e = max(cell_start[c + 1u], s);
    const uint id0 = c + s / CS, next = min(c + 1u + e / CS, cap - 1u);
    for (uint id = id0, b = s; id < next; ++id, b += CS) {
        if (b >= e) {  // the gap
            begin[id] = e;
            continue;
        }
        begin[id] = b;
        const uint end = min(b + CS, e);
        float3 lo = pos[b].xyz, hi = lo;
        for (uint j = b + 1u; j < end; ++j) {
            const float3 p = pos[j].xyz;
            lo = fmin(lo, p);
            hi = fmax(hi, p);
        }
        boxes[2u * id] = (float4)(lo, 0.0f);
        boxes[2u * id + 1u] = (float4)(hi, 0.0f);
    }
    if (c + 1u == cells) begin[next] = e;
}

// The lists of the i-clusters of particles [first, last): a work-item per particle, the members of
// a cluster sharing its ROWS masks (member l of m: rows l, l + m, ...), so that no lane idles.
__kernel void cluster_masks(const uint first, const uint last, const GridParams g, const float support2,
                            __global const float4* pos, __global const uint* cell_of, __global const uint2* ranges,
                            __global const uint* cell_key, __global const uint* cell_start, __global const float4* boxes,
                            __global MASK_T* masks) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    const uint c = cell_of[i], s = cell_start[c];
    const uint id = c + s / CS + (i - s) / CS;
    const uint member = (i - s) % CS, members = min((uint)CS, cell_start[c + 1u] - (i - member));
    const float3 lo_i = boxes[2u * id].xyz, hi_i = boxes[2u * id + 1u].xyz;
    const uint key_i = cell_key[c];
    const uint b_i = key_b(g, key_i);
    // Round-off: the pass computes r2 from offsets and cell shifts in another order; a margin of
    // 1e-4 of the support keeps every pair it finds within the support in a listed cluster.
    const float reach2 = support2 * 1.0002f;
    for (uint r = member; r < ROWS; r += members) {
        const uint2 range = ranges[c * ROWS + r];
        MASK_T m = 0;
        if (range.x < range.y) {
            const uint c0 = cell_of[range.x], c1 = cell_of[range.y - 1u];
            const uint jc0 = c0 + range.x / CS, count = c1 + 1u + range.y / CS - jc0;
            if (count > CLSPH_MASK_BITS) {
                m = ~(MASK_T)0;  // unused: the pass tests the whole row
            } else {
                float3 shift = (float3)(0.0f);
                COMP(shift, AXIS_S) = (float)row_ds(r) * g.cell_s;
                COMP(shift, AXIS_A) = (float)row_da(r) * g.cell_a;
                for (uint cc = c0; cc <= c1; ++cc) {
                    COMP(shift, AXIS_B) = (float)((int)key_b(g, cell_key[cc]) - (int)b_i) * g.cell_b;
                    const uint sc = cell_start[cc], ec = cell_start[cc + 1u];
                    const uint id0 = cc + sc / CS;
                    for (uint k = 0; sc + k * CS < ec; ++k) {
                        const float3 lo_j = boxes[2u * (id0 + k)].xyz + shift;
                        const float3 hi_j = boxes[2u * (id0 + k) + 1u].xyz + shift;
                        const float3 gap = fmax(fmax(lo_j - hi_i, lo_i - hi_j), (float3)(0.0f));
                        if (dot(gap, gap) < reach2) m |= (MASK_T)1 << (id0 + k - jc0);
                    }
                }
            }
        }
        masks[id * ROWS + r] = m;
    }
}

// clsph-bench-interaction only: what the clusters form's pass executes, per work-group of 32
// consecutive particles (a warp): out[0] candidates tested, out[1] hits (self included), out[2]
// the warp's candidate steps (per row, the most candidates any of its lanes tests there; a lane
// of 32 at each step: 32 out[2] / out[0] lane-slots per candidate), out[3] the same for the fine
// form (per row, the longest row of its lanes).
__kernel __attribute__((reqd_work_group_size(32, 1, 1))) void cluster_counts(
    const uint first, const uint last, const GridParams g, const float support2, __global const float4* pos,
    __global const uint* cell_of, __global const uint2* ranges, __global const uint* cell_start,
    __global const uint* cluster_begin, __global const MASK_T* masks, __global uint* out) {
    __local uint sums[4], row_max, fine_max;
    const uint lid = get_local_id(0);
    const uint i = first + (uint)get_global_id(0);
    const bool active = i < last;
    if (lid < 4u) sums[lid] = 0u;
    uint candidates = 0u, hits = 0u, c = 0u, id = 0u;
    float4 self = (float4)(0.0f);
    if (active) {
        self = pos[i];
        c = cell_of[i];
        const uint s = cell_start[c];
        id = c + s / CS + (i - s) / CS;
    }
    const uint key_i = pos_key(self);
    for (uint r = 0; r < ROWS; ++r) {
        uint row = 0u;
        const uint2 range = active ? ranges[c * ROWS + r] : (uint2)(0u, 0u);
        if (range.x < range.y) {
            const uint jc0 = cell_of[range.x] + range.x / CS;
            const uint count = cell_of[range.y - 1u] + 1u + range.y / CS - jc0;
            MASK_T m = count > CLSPH_MASK_BITS ? 0 : masks[id * ROWS + r];
            for (uint t = 0; t < count && t < CLSPH_MASK_BITS; ++t) {
                if (count <= CLSPH_MASK_BITS && !((m >> t) & (MASK_T)1)) continue;
                const uint jb = count > CLSPH_MASK_BITS ? range.x : cluster_begin[jc0 + t];
                const uint je = count > CLSPH_MASK_BITS ? range.y : cluster_begin[jc0 + t + 1u];
                for (uint j = jb; j < je; ++j) {
                    const float4 pj = pos[j];
                    const float3 rij = relative_position(g, key_i, self, pos_key(pj), pj);
                    hits += dot(rij, rij) < support2;
                    ++row;
                }
                if (count > CLSPH_MASK_BITS) break;
            }
        }
        candidates += row;
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0u) row_max = fine_max = 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        atomic_max(&row_max, row);
        atomic_max(&fine_max, range.y > range.x ? range.y - range.x : 0u);
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0u) {
            sums[2] += row_max;
            sums[3] += fine_max;
        }
    }
    atomic_add(&sums[0], candidates);
    atomic_add(&sums[1], hits);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < 4u) out[get_group_id(0) * 4u + lid] = sums[lid];
}
