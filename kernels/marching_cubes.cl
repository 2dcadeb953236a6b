// Marching cubes on a batch of n.w grids of samples (blocks), each nx x ny x nz (numbering:
// marching_cubes.h). Sample (i, j, k) of block b is at origin_b + spacing (i, j, k), stored at
// b nx ny nz + i + nx (j + ny k), block b's sample (0, 0, 0) being lattice point block_at[b] of a
// lattice at `origin` with `spacing`; cubes and edges of a block never reach into another. Passes:
//   mc_edges     per point and axis: 1 where the edge to the next point crosses the iso level
//   (scan)       each crossing edge's vertex index, in place: vertices are welded by construction
//   mc_vertices  each crossing edge's vertex: position by linear interpolation, normal from the
//                field's gradient (central differences at the two ends, pointing outwards)
//   mc_cubes     per cube: its case and how many triangles it makes; (scan) where they go
//   mc_triangles the triangles, as vertex indices
// "Inside" is value >= iso. A vertex never sits exactly on a grid point (its parameter is kept
// within [1e-4, 1 - 1e-4] of the edge), so no triangle degenerates when samples equal iso.
#include "marching_cubes.h"

inline uint point_index(const uint4 n, const uint i, const uint j, const uint k) { return i + n.x * (j + n.y * k); }

__kernel void mc_edges(const uint4 n, const float iso, __global const float* field, __global uint* crossing_all) {
    const uint g = get_global_id(0), per = n.x * n.y * n.z;
    if (g >= per * n.w) return;
    const uint p = g % per;
    __global const float* f = field + (g - p);
    __global uint* crossing = crossing_all + 3u * (g - p);
    const uint i = p % n.x, j = (p / n.x) % n.y, k = p / (n.x * n.y);
    const bool in0 = f[p] >= iso;
    crossing[3u * p + 0u] = i + 1u < n.x && ((f[p + 1u] >= iso) != in0);
    crossing[3u * p + 1u] = j + 1u < n.y && ((f[p + n.x] >= iso) != in0);
    crossing[3u * p + 2u] = k + 1u < n.z && ((f[p + n.x * n.y] >= iso) != in0);
}

inline float3 gradient(const uint4 n, __global const float* f, const uint i, const uint j, const uint k,
                       const float spacing) {
    const uint p = point_index(n, i, j, k);
    const uint im = i > 0u ? i - 1u : i, ip = i + 1u < n.x ? i + 1u : i;
    const uint jm = j > 0u ? j - 1u : j, jp = j + 1u < n.y ? j + 1u : j;
    const uint km = k > 0u ? k - 1u : k, kp = k + 1u < n.z ? k + 1u : k;
    (void)p;
    return (float3)((f[point_index(n, ip, j, k)] - f[point_index(n, im, j, k)]) / ((float)(ip - im) * spacing),
                    (f[point_index(n, i, jp, k)] - f[point_index(n, i, jm, k)]) / ((float)(jp - jm) * spacing),
                    (f[point_index(n, i, j, kp)] - f[point_index(n, i, j, km)]) / ((float)(kp - km) * spacing));
}

__kernel void mc_vertices(const uint4 n, const float iso, const float4 origin, __global const int4* block_at,
                          const float spacing, const uint capacity,
                          __global const float* field, __global const uint* vertex_of,
                          __global float4* position, __global float4* normal, __global uint* edge_of_vertex) {
    const uint ge = get_global_id(0), per = n.x * n.y * n.z;
    // vertex_of is the exclusive scan of the crossing flags (3 per point + 1): a crossing edge's
    // index differs from the next one's.
    // Vertices past `capacity` are not written (their count is still the scan's total).
    if (ge >= 3u * per * n.w || vertex_of[ge + 1u] == vertex_of[ge] || vertex_of[ge] >= capacity) return;
    const uint block = ge / (3u * per), e = ge - block * 3u * per;
    __global const float* f = field + block * per;
    const int4 at = block_at[block];  // lattice index of the block's sample (0, 0, 0)
    const uint p = e / 3u, axis = e % 3u;
    const uint i = p % n.x, j = (p / n.x) % n.y, k = p / (n.x * n.y);
    const uint i1 = i + (axis == 0u), j1 = j + (axis == 1u), k1 = k + (axis == 2u);
    const float f0 = f[p], f1 = f[point_index(n, i1, j1, k1)];
    const float t = clamp((iso - f0) / (f1 - f0), 1e-4f, 1.0f - 1e-4f);
    // From the lattice index, not the block's corner: an edge on a face two blocks share gets the
    // same position from both.
    float3 l = (float3)((float)(at.x + (int)i), (float)(at.y + (int)j), (float)(at.z + (int)k));
    if (axis == 0u) l.x += t;
    if (axis == 1u) l.y += t;
    if (axis == 2u) l.z += t;
    const float3 x = origin.xyz + spacing * l;
    const float3 g = mix(gradient(n, f, i, j, k, spacing), gradient(n, f, i1, j1, k1, spacing), t);
    const float len = length(g);
    const uint v = vertex_of[ge];
    edge_of_vertex[v] = ge;
    position[v] = (float4)(x, 0.0f);
    normal[v] = (float4)(len > 0.0f ? -g / len : (float3)(0.0f), 0.0f);  // outwards: towards lower values
}

inline uint cube_case(const uint4 n, const float iso, __global const float* f, const uint i, const uint j, const uint k) {
    uint c = 0u;
    for (uint corner = 0u; corner < 8u; ++corner) {
        const uint p = point_index(n, i + (corner & 1u), j + ((corner >> 1) & 1u), k + ((corner >> 2) & 1u));
        c |= (uint)(f[p] >= iso) << corner;
    }
    return c;
}

__kernel void mc_cubes(const uint4 n, const float iso, __global const float* field, __global const uchar* table,
                       __global uint* triangles_of) {
    const uint gq = get_global_id(0);
    const uint cx = n.x - 1u, cy = n.y - 1u, cz = n.z - 1u, per = cx * cy * cz;
    if (gq >= per * n.w) return;
    const uint q = gq % per;
    __global const float* f = field + (gq / per) * n.x * n.y * n.z;
    const uint i = q % cx, j = (q / cx) % cy, k = q / (cx * cy);
    const uint c = cube_case(n, iso, f, i, j, k);
    uint count = 0u;
    while (count < CLSPH_MC_MAX_TRIANGLES && table[c * CLSPH_MC_CASE_ENTRIES + 3u * count] != 255u) ++count;
    triangles_of[gq] = count;
}

// The vertex of cube edge e of the cube at (i, j, k): a grid edge (point, axis).
inline uint edge_vertex(const uint4 n, __global const uint* vertex_of, const uint i, const uint j, const uint k,
                        const uint e) {
    uint a, di = 0u, dj = 0u, dk = 0u;
    if (e < 4u) { a = 0u; dj = e & 1u; dk = e >> 1; }
    else if (e < 8u) { a = 1u; di = (e - 4u) & 1u; dk = (e - 4u) >> 1; }
    else { a = 2u; di = (e - 8u) & 1u; dj = (e - 8u) >> 1; }
    return vertex_of[3u * point_index(n, i + di, j + dj, k + dk) + a];
}

__kernel void mc_triangles(const uint4 n, const float iso, const uint capacity, __global const float* field,
                           __global const uchar* table,
                           __global const uint* first_triangle, __global const uint* vertex_of_all,
                           __global uint* triangles) {
    const uint gq = get_global_id(0);
    const uint cx = n.x - 1u, cy = n.y - 1u, cz = n.z - 1u, per = cx * cy * cz;
    if (gq >= per * n.w) return;
    const uint q = gq % per, block = gq / per;
    __global const float* f = field + block * n.x * n.y * n.z;
    __global const uint* vertex_of = vertex_of_all + 3u * block * n.x * n.y * n.z;
    const uint i = q % cx, j = (q / cx) % cy, k = q / (cx * cy);
    const uint c = cube_case(n, iso, f, i, j, k);
    uint out = first_triangle[gq];
    for (uint t = 0u; t < CLSPH_MC_MAX_TRIANGLES; ++t) {
        const uint base = c * CLSPH_MC_CASE_ENTRIES + 3u * t;
        if (table[base] == 255u || out >= capacity) break;  // none past `capacity`
        for (uint v = 0u; v < 3u; ++v) triangles[3u * out + v] = edge_vertex(n, vertex_of, i, j, k, table[base + v]);
        ++out;
    }
}
