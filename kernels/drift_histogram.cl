// The step ahead's first launch on one device with the radix sort's first histogram in it (issue
// 30): drift_settle_key (settle.h: the first kick and drift, settle and key of each particle, as
// cells.cl's drift_settle_keys) for the tile of WG * ITEMS particles of each work-group, then that
// tile's counts of the first pass's digit, as sort_histogram (radix_sort.cl) counts them, so the
// sort starts at its first scatter. The particles are taken striped (consecutive work-items,
// consecutive particles) and their keys counted from local memory in the sort's blocked order;
// counts are integers, so any order gives the same.
//
// Build options: the grid's (grid.h) and the sort's -DWG, -DITEMS, -DDIGIT_BITS.
#include "radix_digits.h"
#include "settle.h"

#define TILE (WG * ITEMS)
#define RADIX_MAX (1u << DIGIT_BITS)
// One padding word per 32, as radix_sort.cl's: the blocked reads hit distinct banks.
#define PAD(i) ((i) + ((i) >> 5))

__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void drift_keys_histogram(
    const uint n, const uint first, const uint end, const uint key_lo, const uint key_hi, const GridParams g,
    __global const float* dt_f, const float rho0, __global float4* pos, __global float4* velrho,
    __global const float4* accel, __global const uint* ids, __global const uint* halt, __global uint* counters,
    __global uint* keys, __global uint* vals, const uint bits, const uint groups, __global uint* counts) {
    __local uint local_counts[3];
    __local uint tile_keys[PAD(TILE)];
    __local uint hist[RADIX_MAX];
    const uint lid = get_local_id(0);
    const uint grp = get_group_id(0);
    const uint radix = 1u << bits;
    for (uint d = lid; d < radix; d += WG) hist[d] = 0;
    begin_counts(local_counts, 3u);  // its barrier covers hist too
    const uint base = grp * TILE;
    const uint count = min((uint)TILE, n - base);
    const float dt = dt_f[0];
    for (uint j = 0; j < ITEMS; ++j) {
        const uint p = lid + j * WG;
        if (p < count) {
            const uint i = base + p;
            const uint key = drift_settle_key(i, first, end, key_lo, key_hi, g, dt, rho0, pos, velrho, accel, ids,
                                              halt, local_counts);
            keys[i] = key;
            vals[i] = i;
            tile_keys[PAD(p)] = key;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    uint key[ITEMS];
    for (uint j = 0; j < ITEMS; ++j) {
        const uint p = lid * ITEMS + j;
        key[j] = p < count ? tile_keys[PAD(p)] : 0u;
    }
    count_digits(key, count, 0u, radix - 1u, hist);
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint d = lid; d < radix; d += WG) counts[d * groups + grp] = hist[d];
    end_counts(local_counts, counters, 3u);
}
