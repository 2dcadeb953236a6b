// Probes: SPH interpolation at arbitrary points from fluid neighbours. Per point (given like a
// particle: offset from its cell centre + key bits in w) it sums over fluid particles j within the
// support: (sum V_j W, sum p_j V_j W), V_j = m / rho_j. The host turns these into a Shepard-
// normalised pressure, or a fluid fraction whose 1/2 crossing along z is the water height.
#include "grid.h"
#include "sph_kernel.h"

inline float2 probe_sums(const uint q, const uint cells, const GridParams g, const SphParams sp,
                         __global const float4* query, __global const uint* cell_key,
                         __global const uint* cell_start, __global const float4* pos,
                         __global const float4* velrho, __global const uint* ids) {
    const float4 x = query[q];
    const uint key = pos_key(x);
    float2 sums = (float2)(0.0f);
    if (key != g.invalid_key) {
        const int s = (int)key_s(g, key), a = (int)key_a(g, key);
        const uint b = key_b(g, key);
        for (uint r = 0; r < ROWS; ++r) {
            uint begin, end;
            if (row_of_point(g, cells, cell_key, cell_start, s, a, b, r, &begin, &end)) {
                for (uint j = begin; j < end; ++j) {
                    if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
                    const float4 pj = pos[j];
                    const float3 d = relative_position(g, key, x, pos_key(pj), pj);
                    const float r2 = dot(d, d);
                    if (r2 >= sp.support2) continue;
                    const float rho = velrho[j].w;
                    const float vw = sp.mass / rho * kernel_w(&sp, sqrt(r2));
                    sums += (float2)(vw, vw * pressure_of(&sp, rho));
                }
            }
        }
    }
    return sums;
}

__kernel void probe_points(const uint points, const uint cells, const GridParams g, const SphParams sp,
                           __global const float4* query, __global const uint* cell_key,
                           __global const uint* cell_start, __global const float4* pos,
                           __global const float4* velrho, __global const uint* ids, __global float2* out) {
    const uint q = get_global_id(0);
    if (q < points) out[q] = probe_sums(q, cells, g, sp, query, cell_key, cell_start, pos, velrho, ids);
}

// The step ahead: the same after a probe step, in the queue, with the cell count read from
// count[0] (CellPipeline::enqueue_tables_bounded).
__kernel void probe_points_counted(const uint points, __global const uint* count, const GridParams g,
                                   const SphParams sp, __global const float4* query, __global const uint* cell_key,
                                   __global const uint* cell_start, __global const float4* pos,
                                   __global const float4* velrho, __global const uint* ids, __global float2* out) {
    const uint q = get_global_id(0);
    if (q < points) out[q] = probe_sums(q, count[0], g, sp, query, cell_key, cell_start, pos, velrho, ids);
}
