// Measurement kernels for clsph-bench-interaction (not used by the simulation).
//   distance_only: the fine neighbour loop with no pair terms: what
//                  the candidate tests alone cost; writes each particle's hit count.
//   warp_counts  : what a warp of 32 consecutive work-items executes in the fine and masked schemes,
//                  emulated in lockstep with local atomics (NVIDIA's OpenCL has no subgroups):
//                  out[0] candidates tested, out[1] hits (pairs inside the support, self included),
//                  out[2] fine: candidate steps at which some lane of the warp hits (the warp runs
//                  the pair terms at each), out[3] masked (distances of 32 candidates into a bit
//                  mask, then only the hits' terms: a form measured slower than fine on the H200
//                  and removed, BENCHMARKS.md): per batch of 32 steps, the busiest lane's hits.
//                  One uint4 of these per work-group (summed on the host).
#include "grid.h"

typedef struct {
    float4 pos;
} CountNeighbour;

typedef struct {
    uint hits;
} CountState;

#define INTERACTION_NAME distance_only
#define INTERACTION_ARGS , __global uint *hits_out
#define NEIGHBOUR_T CountNeighbour
#define LOAD_NEIGHBOUR(nb, j) \
    do {                      \
    } while (0)
#define STATE_T CountState
#define STATE_INIT(st, i, self) (st).hits = 0u
#define PAIR(st, self, nb, i, j, rij, r2) (st).hits += 1u
#define STATE_STORE(st, i) hits_out[i] = (st).hits
#include "neighbour_loop.h"

__kernel __attribute__((reqd_work_group_size(32, 1, 1))) void warp_counts(
    const uint first, const uint last, const GridParams g, const float support2, __global const float4* pos,
    __global const uint* cell_of, __global const uint2* ranges, __global uint* out) {
    __local uint row_len, any_hit, max_pop;
    __local uint sums[4];
    const uint lid = get_local_id(0);
    const uint i = first + (uint)get_global_id(0);
    const bool active = i < last;
    if (lid < 4u) sums[lid] = 0u;
    float4 self = (float4)(0.0f);
    uint key_i = 0u, c = 0u;
    if (active) {
        self = pos[i];
        key_i = pos_key(self);
        c = cell_of[i];
    }
    uint candidates = 0u, hits = 0u;
    for (uint r = 0; r < ROWS; ++r) {
        uint2 range = (uint2)(0u, 0u);
        if (active) range = ranges[c * ROWS + r];
        const uint len = range.y > range.x ? range.y - range.x : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0u) row_len = 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        atomic_max(&row_len, len);
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint steps = row_len;
        for (uint base = 0; base < steps; base += 32u) {
            uint mask = 0u;
            for (uint t = 0; t < 32u && base + t < steps; ++t) {
                bool hit = false;
                if (base + t < len) {
                    const uint j = range.x + base + t;
                    const float4 pj = pos[j];
                    const float3 rij = relative_position(g, key_i, self, pos_key(pj), pj);
                    hit = dot(rij, rij) < support2;
                    candidates += 1u;
                }
                barrier(CLK_LOCAL_MEM_FENCE);
                if (lid == 0u) any_hit = 0u;
                barrier(CLK_LOCAL_MEM_FENCE);
                if (hit) {
                    atomic_or(&any_hit, 1u);
                    mask |= 1u << t;
                    hits += 1u;
                }
                barrier(CLK_LOCAL_MEM_FENCE);
                if (lid == 0u) sums[2] += any_hit;
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            if (lid == 0u) max_pop = 0u;
            barrier(CLK_LOCAL_MEM_FENCE);
            atomic_max(&max_pop, popcount(mask));
            barrier(CLK_LOCAL_MEM_FENCE);
            if (lid == 0u) sums[3] += max_pop;
        }
    }
    atomic_add(&sums[0], candidates);
    atomic_add(&sums[1], hits);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < 4u) out[get_group_id(0) * 4u + lid] = sums[lid];  // summed on the host
}
