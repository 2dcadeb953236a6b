// Exclusive prefix sum of uint, reduce-then-scan: scan_reduce sums each tile, the host scans those
// tile sums (recursively, with these same kernels), and scan_tiles scans each tile again, starting
// from its tile's offset. Input is read twice and output written once (3n words moved, against 4n
// for scan-then-add), and no work-group waits on another (no forward-progress assumption).
// scan_tiles walks the tiles in reverse order: the tiles scan_reduce read last are the likeliest to
// be still in the L2 cache (tens of MB on current GPUs), so part of the second read is free.
//
// Build options: -DWG=<work-group size, power of two> -DITEMS=<elements per work-item, multiple of 4>.
// With `flags` != 0 each input element counts as (x != 0) — the scan that stream compaction needs,
// without a separate pass to turn flags into 0/1.
#include "work_group_scan.h"

#define TILE (WG * ITEMS)

#if ITEMS < 4 || ITEMS % 4 != 0
#error "ITEMS must be a positive multiple of 4 (tiles are read with uint4 loads)"
#endif

inline uint as_count(const uint x, const uint flags) { return flags ? (uint)(x != 0u) : x; }

// sums[g] = sum of tile g of `in` (elements [g * TILE, min((g + 1) * TILE, n))).
__kernel void scan_reduce(__global const uint* in, const uint n, const uint flags, __global uint* sums) {
    __local uint scratch[2 * WG];
    const uint lid = get_local_id(0);
    const uint base = get_group_id(0) * TILE;
    uint sum = 0;
    if (n - base >= TILE) {
        // Full tile: the order of a sum does not matter, so read it striped (consecutive
        // work-items read consecutive uint4s: fully coalesced).
        __global const uint4* in4 = (__global const uint4*)(in + base);
        for (uint j = 0; j < ITEMS / 4; ++j) {
            const uint4 v = in4[lid + j * WG];
            sum += as_count(v.x, flags) + as_count(v.y, flags) + as_count(v.z, flags) + as_count(v.w, flags);
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) {
            const uint i = base + lid + j * WG;
            if (i < n) sum += as_count(in[i], flags);
        }
    }
    uint total;
    (void)work_group_exclusive_scan(sum, scratch, &total);
    if (lid == 0) sums[get_group_id(0)] = total;
}

// Local arrays indexed by tile position get one padding word per 32, so that both the striped
// (coalesced) and the blocked (one work-item, ITEMS consecutive) accesses hit distinct banks.
#define PAD(i) ((i) + ((i) >> 5))

// out[i] = tile_offset + exclusive scan of the tile up to i, for the tile's elements; the group
// holding element n - 1 also writes out[n] (the grand total). `in` and `out` may be the same
// buffer: each tile is read completely before any of it is written, and tiles do not overlap.
// Without offsets (has_offsets == 0: a single-tile scan) the tile offset is 0.
__kernel void scan_tiles(__global const uint* in, __global uint* out, const uint n, const uint flags,
                         __global const uint* tile_offsets, const uint has_offsets) {
    __local uint scratch[2 * WG];
#if ITEMS > 4
    // Each work-item scans ITEMS consecutive elements (the blocked arrangement), but global memory
    // is read and written striped (consecutive work-items, consecutive uint4s: fully coalesced)
    // and the tile is transposed through local memory in between.
    __local uint staged[PAD(TILE)];
#endif
    const uint lid = get_local_id(0);
    const uint tile = get_num_groups(0) - 1u - get_group_id(0);  // reverse order: see the top
    const uint base = tile * TILE;
    const bool full = n - base >= TILE;
    uint x[ITEMS];
#if ITEMS > 4
    if (full) {
        __global const uint4* in4 = (__global const uint4*)(in + base);
        for (uint j = 0; j < ITEMS / 4; ++j) {
            const uint q = lid + j * WG;
            const uint4 v = in4[q];
            staged[PAD(4 * q + 0)] = v.x;
            staged[PAD(4 * q + 1)] = v.y;
            staged[PAD(4 * q + 2)] = v.z;
            staged[PAD(4 * q + 3)] = v.w;
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) {
            const uint i = lid + j * WG;
            staged[PAD(i)] = base + i < n ? in[base + i] : 0u;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint j = 0; j < ITEMS; ++j) x[j] = as_count(staged[PAD(lid * ITEMS + j)], flags);
#else
    const uint first = base + lid * ITEMS;  // one uint4 per work-item: blocked is already coalesced
    if (full) {
        const uint4 v = *(__global const uint4*)(in + first);
        x[0] = as_count(v.x, flags);
        x[1] = as_count(v.y, flags);
        x[2] = as_count(v.z, flags);
        x[3] = as_count(v.w, flags);
    } else {
        for (uint j = 0; j < ITEMS; ++j) x[j] = first + j < n ? as_count(in[first + j], flags) : 0u;
    }
#endif
    uint sum = 0;
    for (uint j = 0; j < ITEMS; ++j) sum += x[j];
    uint total;
    const uint offset = (has_offsets ? tile_offsets[tile] : 0u);
    uint running = offset + work_group_exclusive_scan(sum, scratch, &total);
    // Exclusive values in place of the inputs.
    for (uint j = 0; j < ITEMS; ++j) {
        const uint v = x[j];
        x[j] = running;
        running += v;
    }
#if ITEMS > 4
    for (uint j = 0; j < ITEMS; ++j) staged[PAD(lid * ITEMS + j)] = x[j];
    barrier(CLK_LOCAL_MEM_FENCE);
    if (full) {
        __global uint4* out4 = (__global uint4*)(out + base);
        for (uint j = 0; j < ITEMS / 4; ++j) {
            const uint q = lid + j * WG;
            out4[q] = (uint4)(staged[PAD(4 * q)], staged[PAD(4 * q + 1)], staged[PAD(4 * q + 2)], staged[PAD(4 * q + 3)]);
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) {
            const uint i = lid + j * WG;
            if (base + i < n) out[base + i] = staged[PAD(i)];
        }
    }
#else
    if (full) {
        *(__global uint4*)(out + first) = (uint4)(x[0], x[1], x[2], x[3]);
    } else {
        for (uint j = 0; j < ITEMS; ++j)
            if (first + j < n) out[first + j] = x[j];
    }
#endif
    if (lid == 0 && n - base <= TILE) out[n] = offset + total;
}
