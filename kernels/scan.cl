// Exclusive prefix sum of uint, reduce-then-scan: scan_reduce sums each tile, the host scans those
// tile sums (recursively, with these same kernels), and scan_tiles scans each tile again, starting
// from its tile's offset. Input is read twice and output written once (3n words moved, against 4n
// for scan-then-add), and no work-group waits on another (no forward-progress assumption).
// scan_tiles walks the tiles in reverse order: the tiles scan_reduce read last are the likeliest to
// be still in the L2 cache (tens of MB on current GPUs), so part of the second read is free.
//
// Build options: -DWG=<work-group size, power of two> -DITEMS=<elements per work-item, multiple of 4>.
// `flags` says what an input element counts as: 0 its value; 1 (x != 0), the scan that stream
// compaction needs, without a separate pass to turn flags into 0/1; 2 whether it starts a run of
// equal values (i == 0 or in[i] != in[i - 1]: the first particle of each cell in the sorted keys,
// so the compaction of cells needs no pass of flags either; `in` and `out` must then differ, since
// an element's count reads the element before it, which may lie in another tile).
#include "work_group_scan.h"

#define TILE (WG * ITEMS)

#if ITEMS < 4 || ITEMS % 4 != 0
#error "ITEMS must be a positive multiple of 4 (tiles are read with uint4 loads)"
#endif

#define FLAGS_STARTS 2u

inline uint as_count(const uint x, const uint flags) { return flags ? (uint)(x != 0u) : x; }

// What element i of `in` counts as, its value being x.
inline uint count_of(__global const uint* in, const uint i, const uint x, const uint flags) {
    if (flags == FLAGS_STARTS) return (uint)(i == 0u || x != in[i - 1u]);
    return as_count(x, flags);
}

// The counts of elements i .. i + 3, their values being v.
inline uint4 counts_of4(__global const uint* in, const uint i, const uint4 v, const uint flags) {
    if (flags == FLAGS_STARTS)
        return (uint4)((uint)(i == 0u || v.x != in[i - 1u]), (uint)(v.y != v.x), (uint)(v.z != v.y), (uint)(v.w != v.z));
    return (uint4)(as_count(v.x, flags), as_count(v.y, flags), as_count(v.z, flags), as_count(v.w, flags));
}

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
            const uint q = lid + j * WG;
            const uint4 c = counts_of4(in, base + 4u * q, in4[q], flags);
            sum += c.x + c.y + c.z + c.w;
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) {
            const uint i = base + lid + j * WG;
            if (i < n) sum += count_of(in, i, in[i], flags);
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
// Without offsets (has_offsets == 0: a single-tile scan) the tile offset is 0; with has_offsets
// == 1 it is tile_offsets[tile] (the tile sums, scanned); with has_offsets == 2 tile_offsets holds
// the tile sums as scan_reduce left them and each work-group adds up those before its own (a
// launch fewer than scanning them: integer sums, so the same offsets in any order).
// Every work-item of every scan_tiles calls it (0 unless has_offsets == 2): its barriers inside a
// branch corrupted pocl's basic device (see radix_sort.cl, digit_bases).
inline uint offset_of_tile(__global const uint* sums, const uint tile, const uint has_offsets, __local uint* scratch) {
    uint part = 0;
    const uint before = has_offsets == 2u ? tile : 0u;
    for (uint t = get_local_id(0); t < before; t += WG) part += sums[t];
    uint total;
    (void)work_group_exclusive_scan(part, scratch, &total);
    return total;
}

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
            const uint4 c = counts_of4(in, base + 4u * q, in4[q], flags);
            staged[PAD(4 * q + 0)] = c.x;
            staged[PAD(4 * q + 1)] = c.y;
            staged[PAD(4 * q + 2)] = c.z;
            staged[PAD(4 * q + 3)] = c.w;
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) {
            const uint i = lid + j * WG;
            staged[PAD(i)] = base + i < n ? count_of(in, base + i, in[base + i], flags) : 0u;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint j = 0; j < ITEMS; ++j) x[j] = staged[PAD(lid * ITEMS + j)];
#else
    const uint first = base + lid * ITEMS;  // one uint4 per work-item: blocked is already coalesced
    if (full) {
        const uint4 c = counts_of4(in, first, *(__global const uint4*)(in + first), flags);
        x[0] = c.x;
        x[1] = c.y;
        x[2] = c.z;
        x[3] = c.w;
    } else {
        for (uint j = 0; j < ITEMS; ++j) x[j] = first + j < n ? count_of(in, first + j, in[first + j], flags) : 0u;
    }
#endif
    uint sum = 0;
    for (uint j = 0; j < ITEMS; ++j) sum += x[j];
    uint total;
    const uint folded = offset_of_tile(tile_offsets, tile, has_offsets, scratch);
    const uint offset = has_offsets == 2u ? folded : has_offsets ? tile_offsets[tile] : 0u;
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
