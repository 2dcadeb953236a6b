// The free surface on the device (host/src/surface/device_surface.cpp): blocks of 8^3 cubes of a
// lattice of samples (spacing `spacing`, sample (I, J, K) at the domain's min corner + spacing
// (I, J, K)), found from the fluid particles, sampled, meshed by marching_cubes.cl, welded.
//   surface_count    per owned particle: fluid particles per block (a dense grid of blocks)
//   surface_flag     per block: active where it or a neighbour holds fluid, unless it and all 26
//                    neighbours are nearly full (inside)
//   (scan)           each active block's slot, in block-key order
//   surface_compact  the active blocks' keys and lattice corners, by slot
//   surface_field    per sample of an active block: the fluid fraction sum V_j W, 0 outside the
//                    columns [col_lo, col_hi) this device owns; a work-group per block
//   surface_gather   the blocks one device meshes, when several share the surface
//   surface_slots    a dense map block key -> slot, for the weld
//   surface_weld     per vertex of marching_cubes.cl (one per crossing edge of each block): the
//                    vertex of the same lattice edge in the lowest-keyed block meshed here, and
//                    whether that is its own block; (scan) the welded vertices' indices
//   surface_welded   the welded vertices, and each vertex's welded index
//   surface_remap    triangles onto the welded vertices
// Block keys are bx + nbx (by + nby bz); a block's sample (i, j, k) (0..8 per axis, faces shared
// with neighbours) is at i + 9 (j + 9 k) of its 729 in the field.
#include "grid.h"
#include "sph_kernel.h"

#define SURFACE_CUBES 8
#define SURFACE_SAMPLES 9
#define SURFACE_PER_BLOCK (SURFACE_SAMPLES * SURFACE_SAMPLES * SURFACE_SAMPLES)
#define SURFACE_NONE 0xffffffffu

inline uint block_key(const uint4 nb, const int i, const int j, const int k) {
    return (uint)i + nb.x * ((uint)j + nb.y * (uint)k);
}

inline bool block_inside(const uint4 nb, const int i, const int j, const int k) {
    return i >= 0 && j >= 0 && k >= 0 && (uint)i < nb.x && (uint)j < nb.y && (uint)k < nb.z;
}

// A particle's position relative to the domain's min corner, from its cell and offset.
inline float3 relative_of(const GridParams g, const float4 p) {
    const uint key = pos_key(p);
    float3 r;
    S_OF(r) = ((float)key_s(g, key) + 0.5f) * g.cell_s + S_OF(p);
    A_OF(r) = ((float)key_a(g, key) + 0.5f) * g.cell_a + A_OF(p);
    B_OF(r) = ((float)key_b(g, key) + 0.5f) * g.cell_b + B_OF(p);
    return r;
}

__kernel void surface_count(const uint first, const uint end, const GridParams g, const uint4 nb,
                            const float block_edge, __global const float4* pos, __global const uint* ids,
                            __global uint* count) {
    const uint i = first + get_global_id(0);
    if (i >= end || (ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const float4 p = pos[i];
    if (pos_key(p) == g.invalid_key) return;
    const float3 b = floor(relative_of(g, p) / block_edge);
    const int bi = (int)b.x, bj = (int)b.y, bk = (int)b.z;
    if (block_inside(nb, bi, bj, bk)) atomic_inc(&count[block_key(nb, bi, bj, bk)]);
}

__kernel void surface_flag(const uint4 nb, const uint full, __global const uint* count, __global uint* flag) {
    const uint key = get_global_id(0);
    if (key >= nb.x * nb.y * nb.z) return;
    const int i = (int)(key % nb.x), j = (int)((key / nb.x) % nb.y), k = (int)(key / (nb.x * nb.y));
    bool fluid = false, inside = true;
    for (int dk = -1; dk <= 1; ++dk)
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                if (!block_inside(nb, i + di, j + dj, k + dk)) {
                    inside = false;
                    continue;
                }
                const uint c = count[block_key(nb, i + di, j + dj, k + dk)];
                fluid = fluid || c > 0u;
                inside = inside && c >= full;
            }
    flag[key] = fluid && !inside;
}

__kernel void surface_compact(const uint4 nb, const uint capacity, __global const uint* flag,
                              __global const uint* slot_of_flag, __global uint* active, __global int4* block_at) {
    const uint key = get_global_id(0);
    if (key >= nb.x * nb.y * nb.z || !flag[key]) return;
    const uint slot = slot_of_flag[key];
    if (slot >= capacity) return;  // past the capacity: counted (the scan's total), not kept
    active[slot] = key;
    block_at[slot] = (int4)((int)(key % nb.x) * SURFACE_CUBES, (int)((key / nb.x) % nb.y) * SURFACE_CUBES,
                            (int)(key / (nb.x * nb.y)) * SURFACE_CUBES, 0);
}

// One axis of a sample's cell and offset (Grid::locate_axis, in float): false outside the domain.
inline bool locate_axis(const float x, const float cell, const uint n, const uint periodic, uint* c, float* off) {
    float rel = x;
    if (periodic) {
        const float len = cell * (float)n;
        rel -= floor(rel / len) * len;
    }
    float ci = floor(rel / cell);
    if (periodic && ci >= (float)n) ci = (float)(n - 1u);
    if (!(ci >= 0.0f) || ci >= (float)n) return false;
    *c = (uint)ci;
    *off = rel - (ci + 0.5f) * cell;
    return true;
}

// A work-group per block: the block's candidate particles (the rows of cells within the support
// of its samples' box, found by the group's items in parallel) are handed out to its items one
// particle each, and each particle adds its share V_j W to the samples within its support, in
// local memory. The sums are in 32-bit fixed point (2^-24), so they are the same whatever order
// the items add in: the field does not depend on the device or on the work-group's schedule.
// Before (a gather: every sample tested every staged candidate) each sample tested ~20x more
// particles than it hit.
#ifndef SURFACE_WG
#define SURFACE_WG 128
#endif
#define SURFACE_FIXED 16777216.0f  // 2^24: the field's sums, in fixed point

// The cells [lo, hi] along one key axis that hold particles within `reach` of [x0, x1].
inline void cell_span(const float x0, const float x1, const float reach, const float cell, const uint n,
                      const uint periodic, int* lo, int* hi) {
    *lo = (int)floor((x0 - reach) / cell);
    *hi = (int)floor((x1 + reach) / cell);
    if (periodic) {
        if (*hi - *lo + 1 > (int)n) *hi = *lo + (int)n - 1;
    } else {
        *lo = max(*lo, 0);
        *hi = min(*hi, (int)n - 1);
    }
}

__kernel __attribute__((reqd_work_group_size(SURFACE_WG, 1, 1)))
void surface_field(const uint blocks, const float spacing, const uint col_lo, const uint col_hi,
                   const uint cells, const GridParams g, const SphParams sp,
                   __global const int4* block_at, __global const uint* cell_key,
                   __global const uint* cell_start, __global const float4* pos,
                   __global const float4* velrho, __global const uint* ids, __global const uint* totals,
                   __global float* field) {
    __local uint acc[SURFACE_PER_BLOCK];
    __local uint row_begin[SURFACE_WG], row_first[SURFACE_WG + 1];  // a batch of rows, flattened
    const uint b = get_group_id(0), lid = get_local_id(0);
    const float mass = sp.mass, support2 = sp.support2, support = sqrt(sp.support2);
    if (b >= blocks) return;  // whole groups only: the barriers below stay uniform
    if (b >= totals[0]) {     // a block of the capacity past the live ones: outside, it makes nothing
        for (uint p = lid; p < SURFACE_PER_BLOCK; p += SURFACE_WG) field[b * SURFACE_PER_BLOCK + p] = 0.0f;
        return;
    }
    const int4 at = block_at[b];
    const float3 x0 = spacing * (float3)((float)at.x, (float)at.y, (float)at.z);
    const float3 x1 = x0 + spacing * (float)SURFACE_CUBES;
    // Axis a wraps where periodic: a particle is taken at its image nearest the block's centre.
    const float period_a = (float)g.n_a * g.cell_a, centre_a = A_OF(x0) + 0.5f * spacing * (float)SURFACE_CUBES;
    const float inv_spacing = 1.0f / spacing;
    for (uint p = lid; p < SURFACE_PER_BLOCK; p += SURFACE_WG) acc[p] = 0u;
    // The block's rows: cells within the support of its samples' box. Kept cell tables
    // (run.list_buffer) list a particle in the cell it was sorted into, up to half the buffer from
    // where it is now; the split axis's cells are the support plus the buffer wide (never
    // stretched), so the rows reach half that margin further (none without a buffer).
    const float reach = support + 0.5f * fmax(g.cell_s - support, 0.0f);
    int s_lo, s_hi, a_lo, a_hi, b_lo, b_hi;
    cell_span(S_OF(x0), S_OF(x1), reach, g.cell_s, g.n_s, 0u, &s_lo, &s_hi);
    cell_span(A_OF(x0), A_OF(x1), reach, g.cell_a, g.n_a, g.periodic_a, &a_lo, &a_hi);
    cell_span(B_OF(x0), B_OF(x1), reach, g.cell_b, g.n_b, 0u, &b_lo, &b_hi);
    const int na = a_hi - a_lo + 1;
    const uint rows = (s_hi >= s_lo && na > 0 && b_lo <= b_hi) ? (uint)((s_hi - s_lo + 1) * na) : 0u;
    for (uint batch = 0; batch < rows; batch += SURFACE_WG) {
        const uint in_batch = min((uint)SURFACE_WG, rows - batch);
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < in_batch) {
            const uint r = batch + lid;
            const int s = s_lo + (int)(r / (uint)na), a0 = a_lo + (int)(r % (uint)na);
            const int a = a0 < 0 ? a0 + (int)g.n_a : a0 >= (int)g.n_a ? a0 - (int)g.n_a : a0;
            const uint begin = cell_start[lower_bound_key(cell_key, cells, make_key(g, (uint)s, (uint)a, (uint)b_lo))];
            const uint end = cell_start[lower_bound_key(cell_key, cells, make_key(g, (uint)s, (uint)a, (uint)b_hi) + 1u)];
            row_begin[lid] = begin;
            row_first[lid + 1u] = end - begin;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0u) {
            row_first[0] = 0u;
            for (uint r = 1; r <= in_batch; ++r) row_first[r] += row_first[r - 1u];
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint total = row_first[in_batch];
        for (uint t = lid; t < total; t += SURFACE_WG) {
            uint lo = 0u, hi = in_batch;  // the row holding candidate t: row_first[lo] <= t < row_first[lo + 1]
            while (hi - lo > 1u) {
                const uint mid = (lo + hi) >> 1;
                if (row_first[mid] <= t) lo = mid; else hi = mid;
            }
            const uint j = row_begin[lo] + (t - row_first[lo]);
            if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
            float3 r = relative_of(g, pos[j]);
            if (g.periodic_a) {
                const float da = A_OF(r) - centre_a;
                A_OF(r) = centre_a + (da - period_a * rint(da / period_a));
            }
            const float3 d0 = r - x0;
            const float v = mass / velrho[j].w;
            const int3 top = (int3)(SURFACE_SAMPLES - 1);
            const int3 lo3 = max(convert_int3(ceil((d0 - support) * inv_spacing)), (int3)(0));
            const int3 hi3 = min(convert_int3(floor((d0 + support) * inv_spacing)), top);
            for (int k = lo3.z; k <= hi3.z; ++k) {
                const float dz = d0.z - spacing * (float)k;
                for (int jj = lo3.y; jj <= hi3.y; ++jj) {
                    const float dy = d0.y - spacing * (float)jj, dyz2 = dy * dy + dz * dz;
                    if (dyz2 >= support2) continue;
                    for (int i = lo3.x; i <= hi3.x; ++i) {
                        const float dx = d0.x - spacing * (float)i, r2 = dx * dx + dyz2;
                        if (r2 < support2)
                            atomic_add(&acc[(uint)i + SURFACE_SAMPLES * ((uint)jj + SURFACE_SAMPLES * (uint)k)],
                                       convert_uint_rte(v * kernel_w(&sp, sqrt(r2)) * SURFACE_FIXED));
                    }
                }
            }
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    // Samples outside the domain or outside the columns this device owns are 0.
    for (uint p = lid; p < SURFACE_PER_BLOCK; p += SURFACE_WG) {
        const int3 local_at = (int3)((int)(p % SURFACE_SAMPLES), (int)((p / SURFACE_SAMPLES) % SURFACE_SAMPLES),
                                     (int)(p / (SURFACE_SAMPLES * SURFACE_SAMPLES)));
        const float3 x = spacing * (float3)((float)(at.x + local_at.x), (float)(at.y + local_at.y), (float)(at.z + local_at.z));
        uint s, a, bb;
        float os, oa, ob;
        const bool live = locate_axis(S_OF(x), g.cell_s, g.n_s, 0u, &s, &os) && s >= col_lo && s < col_hi &&
                          locate_axis(A_OF(x), g.cell_a, g.n_a, g.periodic_a, &a, &oa) &&
                          locate_axis(B_OF(x), g.cell_b, g.n_b, 0u, &bb, &ob);
        field[b * SURFACE_PER_BLOCK + p] = live ? (float)acc[p] * (1.0f / SURFACE_FIXED) : 0.0f;
    }
}

// The live counts (totals: blocks, vertices, triangles, welded vertices), each bounded by its
// capacity, which the launches are sized for.
__kernel void surface_total(__global const uint* scanned, const uint at, const uint which, __global uint* totals) {
    if (get_global_id(0) == 0u) totals[which] = scanned[at];
}

__kernel void surface_slots(const uint blocks, __global const uint* totals, __global uint* active,
                            __global uint* slot_of) {
    const uint slot = get_global_id(0);
    if (slot < min(blocks, totals[0])) slot_of[active[slot]] = slot;
}

__kernel void surface_weld(const uint vertices, __global const uint* totals, const uint4 nb,
                           __global const int4* block_at, __global const uint* slot_of,
                           __global const uint* edge_of_vertex, __global const uint* vertex_of, __global uint* own,
                           __global uint* target) {
    const uint v = get_global_id(0);
    if (v >= vertices) return;
    if (v >= totals[1]) {  // past the live vertices: not kept by the weld's scan
        own[v] = 0u;
        return;
    }
    const uint per_edges = 3u * SURFACE_PER_BLOCK;
    const uint ge = edge_of_vertex[v], b = ge / per_edges, e = ge - b * per_edges, p = e / 3u, axis = e % 3u;
    const int4 at = block_at[b];
    const int I[3] = {at.x + (int)(p % SURFACE_SAMPLES), at.y + (int)((p / SURFACE_SAMPLES) % SURFACE_SAMPLES),
                      at.z + (int)(p / (SURFACE_SAMPLES * SURFACE_SAMPLES))};
    // The blocks holding this edge: along the edge's axis one; across it two where the edge lies
    // on a block face (lattice index a multiple of 8). Lowest key first: k, then j, then i.
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        hi[d] = I[d] / SURFACE_CUBES;
        lo[d] = ((uint)d != axis && I[d] % SURFACE_CUBES == 0 && hi[d] > 0) ? hi[d] - 1 : hi[d];
    }
    uint found = SURFACE_NONE, at_edge = 0u;
    for (int ck = lo[2]; ck <= hi[2] && found == SURFACE_NONE; ++ck)
        for (int cj = lo[1]; cj <= hi[1] && found == SURFACE_NONE; ++cj)
            for (int ci = lo[0]; ci <= hi[0] && found == SURFACE_NONE; ++ci) {
                if (!block_inside(nb, ci, cj, ck)) continue;
                const uint s = slot_of[block_key(nb, ci, cj, ck)];
                if (s == SURFACE_NONE) continue;
                const uint lp = (uint)(I[0] - ci * SURFACE_CUBES) +
                                SURFACE_SAMPLES * ((uint)(I[1] - cj * SURFACE_CUBES) +
                                                   SURFACE_SAMPLES * (uint)(I[2] - ck * SURFACE_CUBES));
                found = s;
                at_edge = s * per_edges + 3u * lp + axis;
            }
    // The vertex's own block is always among them, so `found` is set.
    own[v] = found == b;
    target[v] = vertex_of[at_edge];
}

__kernel void surface_welded(const uint vertices, __global const uint* totals, const uint4 lattice,
                             __global const uint* own,
                             __global const uint* welded_index, __global const uint* target,
                             __global const float4* position, __global const float4* normal,
                             __global const uint* edge_of_vertex, __global const int4* block_at,
                             __global uint* remap, __global float4* out_position, __global float4* out_normal,
                             __global uint2* out_edge) {
    const uint v = get_global_id(0);
    if (v >= min(vertices, totals[1])) return;
    const uint to = target[v];  // past the capacity only when a redo follows: nothing to read there
    remap[v] = to < vertices ? welded_index[to] : 0u;
    if (!own[v]) return;
    const uint w = welded_index[v];
    out_position[w] = position[v];
    out_normal[w] = normal[v];
    // The lattice edge as a 64-bit number ((K ny + J) nx + I) 3 + axis, for the host's weld across
    // devices: lo and hi words.
    const uint per_edges = 3u * SURFACE_PER_BLOCK;
    const uint ge = edge_of_vertex[v], b = ge / per_edges, e = ge - b * per_edges, p = e / 3u;
    const int4 at = block_at[b];
    const ulong I = (ulong)(at.x + (int)(p % SURFACE_SAMPLES)), J = (ulong)(at.y + (int)((p / SURFACE_SAMPLES) % SURFACE_SAMPLES)),
                K = (ulong)(at.z + (int)(p / (SURFACE_SAMPLES * SURFACE_SAMPLES)));
    const ulong edge = ((K * (ulong)lattice.y + J) * (ulong)lattice.x + I) * 3ul + (ulong)(e % 3u);
    out_edge[w] = (uint2)((uint)(edge & 0xffffffffu), (uint)(edge >> 32));
}

__kernel void surface_remap(const uint triangles_cap, const uint vertices_cap, __global const uint* totals,
                            __global const uint* remap, __global uint* triangles) {
    const uint t = get_global_id(0);
    if (t >= 3u * min(triangles_cap, totals[2])) return;
    const uint v = triangles[t];
    triangles[t] = v < min(vertices_cap, totals[1]) ? remap[v] : 0u;  // past them only when a redo follows
}

__kernel void surface_gather(const uint blocks, __global const uint* slots, __global const uint* active,
                             __global const int4* block_at, __global const float* field, __global uint* out_active,
                             __global int4* out_block_at, __global float* out_field) {
    const uint gid = get_global_id(0);
    if (gid >= blocks * SURFACE_PER_BLOCK) return;
    const uint b = gid / SURFACE_PER_BLOCK, p = gid - b * SURFACE_PER_BLOCK, from = slots[b];
    out_field[gid] = field[from * SURFACE_PER_BLOCK + p];
    if (p == 0u) {
        out_active[b] = active[from];
        out_block_at[b] = block_at[from];
    }
}
