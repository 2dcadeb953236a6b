// Probes: SPH interpolation at arbitrary points from fluid neighbours. Per point (given like a
// particle: offset from its cell centre + key bits in w) it sums over fluid particles j within the
// support: (sum V_j W, sum p_j V_j W), V_j = m / rho_j. The host turns these into a Shepard-
// normalised pressure, or a fluid fraction whose 1/2 crossing along z is the water height.
#include "probe_sums.h"

inline float2 probe_sums(const uint q, const uint cells, const GridParams g, const SphParams sp,
                         __global const float4* query, __global const uint* cell_key,
                         __global const uint* cell_start, __global const float4* pos,
                         __global const float4* velrho, __global const uint* ids) {
    return probe_sums_at(query[q], cells, g, sp, cell_key, cell_start, pos, velrho, ids);
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
