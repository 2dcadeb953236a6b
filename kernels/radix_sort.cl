// One pass of a stable LSD radix sort of (uint key, uint value) pairs, on the digit of `bits` bits
// (1..DIGIT_BITS) at bit `shift` of the key. The array is cut into tiles of TILE pairs, one per
// work-group, in the same way by both kernels:
//   sort_histogram  counts the digits of each tile into a digit-major table counts[d * groups + g];
//   (the host scans that table, so entry (d, g) becomes where tile g's first key with digit d goes);
//   sort_scatter    sorts its tile by the digit in local memory (stable) and writes each digit's run
//                   of the tile to consecutive addresses from that entry on. With `fold` the table
//                   is not scanned: each work-group adds up the entries before its own (few tiles:
//                   a launch or more fewer; integer sums, so the same addresses).
// Key bits outside the digit never affect the order and are carried along unchanged.
//
// Each array is passed as a buffer and an element offset into it, so that the ping-pong of a sort
// can live in a buffer that another stage owns (the reorder scratch); offsets are multiples of 4
// (the uint4 loads stay aligned).
//
// Build options: -DWG=<work-group size, power of two, >= 16> -DITEMS=<pairs per work-item,
// multiple of 4> -DDIGIT_BITS=<widest digit, 1..8>.
#include "radix_digits.h"
#include "work_group_scan.h"

#define TILE (WG * ITEMS)
#define RADIX_MAX (1u << DIGIT_BITS)
// Local arrays indexed by tile position get one padding word per 32 words, so that work-items
// reading ITEMS consecutive positions each (the blocked arrangement) hit distinct banks.
#define PAD(i) ((i) + ((i) >> 5))
#define PADDED_TILE PAD(TILE)
// Ranking works on sub-digits of up to 4 bits: 16 counters per work-item, packed as 16-bit halves
// of COUNTER_WORDS words (digit d in word d % 8, the high half when d >= 8).
#define COUNTER_WORDS 8u

#if ITEMS < 4 || ITEMS % 4 != 0
#error "ITEMS must be a positive multiple of 4 (tiles are read with uint4 loads)"
#endif
#if TILE >= 65536
#error "ranks within a tile are packed in 16 bits: WG * ITEMS must stay below 65536"
#endif
#if DIGIT_BITS < 1 || DIGIT_BITS > 8
#error "DIGIT_BITS must be 1..8"
#endif

// Reads this work-item's ITEMS consecutive elements of the tile starting at `base` (the blocked
// arrangement: work-item order is tile order, which makes stable ranking simple). Elements past
// `count` read as `fill`. Full tiles use aligned uint4 loads.
inline void load_blocked(__global const uint* src, const uint base, const uint count, const uint fill, uint* x) {
    const uint first = get_local_id(0) * ITEMS;
    if (count == TILE) {
        __global const uint4* src4 = (__global const uint4*)(src + base + first);
        for (uint j = 0; j < ITEMS / 4; ++j) {
            const uint4 v = src4[j];
            x[4 * j + 0] = v.x;
            x[4 * j + 1] = v.y;
            x[4 * j + 2] = v.z;
            x[4 * j + 3] = v.w;
        }
    } else {
        for (uint j = 0; j < ITEMS; ++j) x[j] = first + j < count ? src[base + first + j] : fill;
    }
}

__kernel void sort_histogram(__global const uint* keys, const uint keys_at, const uint n, const uint shift,
                             const uint bits, const uint groups, __global uint* counts) {
    keys += keys_at;
    __local uint hist[RADIX_MAX];
    const uint lid = get_local_id(0);
    const uint g = get_group_id(0);
    const uint radix = 1u << bits;
    const uint mask = radix - 1u;
    for (uint d = lid; d < radix; d += WG) hist[d] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);

    const uint base = g * TILE;
    const uint count = min((uint)TILE, n - base);
    uint key[ITEMS];
    load_blocked(keys, base, count, 0u, key);
    count_digits(key, count, shift, mask, hist);
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint d = lid; d < radix; d += WG) counts[d * groups + g] = hist[d];
}

// Stable local sort of the tile on the `bits` (<= 4) bits at `shift`: each work-item ranks its
// keys with private counters in local memory, a work-group scan turns the counters into tile
// positions (digit-major, work-item order within a digit: hence stable), and the pairs are moved
// to those positions in exch (keys in [0, PADDED_TILE), values after). The counters live in exch
// too: they are dead by the time the pairs are written.
inline void rank_and_exchange(uint* key, uint* val, const uint shift, const uint bits, __local uint* exch,
                              __local uint* scratch) {
    const uint lid = get_local_id(0);
    const uint mask = (1u << bits) - 1u;
    barrier(CLK_LOCAL_MEM_FENCE);  // exch may still be read by the previous step
    for (uint w = 0; w < COUNTER_WORDS; ++w) exch[PAD(w * WG + lid)] = 0;
    // Each work-item only touches its own counters here: no barrier needed yet.
    uint rank[ITEMS];
    for (uint j = 0; j < ITEMS; ++j) {
        const uint d = (key[j] >> shift) & mask;
        const uint at = PAD((d & 7u) * WG + lid);
        const uint high = (d >> 3) * 16u;  // bit offset of the half: 0 or 16
        const uint old = exch[at];
        exch[at] = old + (1u << high);
        rank[j] = (old >> high) & 0xffffu;  // keys of this digit earlier in this work-item
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    // Scan all counters in (word, work-item) order; work-item lid rakes the COUNTER_WORDS
    // consecutive counters [lid * 8, lid * 8 + 8) of that order. Both halves scan at once: a tile
    // holds < 65536 keys, so the low half never carries into the high one.
    uint sum = 0;
    for (uint i = 0; i < COUNTER_WORDS; ++i) sum += exch[PAD(lid * COUNTER_WORDS + i)];
    uint total;
    uint prefix = work_group_exclusive_scan(sum, scratch, &total);
    for (uint i = 0; i < COUNTER_WORDS; ++i) {
        const uint at = PAD(lid * COUNTER_WORDS + i);
        const uint c = exch[at];
        exch[at] = prefix;
        prefix += c;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    // Digits 8..15 (high halves) come after all of digits 0..7, whose count is the low half of the total.
    const uint low_total = total & 0xffffu;
    for (uint j = 0; j < ITEMS; ++j) {
        const uint d = (key[j] >> shift) & mask;
        const uint high = (d >> 3) * 16u;  // bit offset of the half: 0 or 16
        const uint start = (exch[PAD((d & 7u) * WG + lid)] >> high) & 0xffffu;
        rank[j] += start + (high ? low_total : 0u);
    }
    barrier(CLK_LOCAL_MEM_FENCE);  // all counters read before the pairs overwrite them
    for (uint j = 0; j < ITEMS; ++j) {
        exch[PAD(rank[j])] = key[j];
        exch[PADDED_TILE + PAD(rank[j])] = val[j];
    }
}

// digit_base[d] = where tile g's first key with digit d goes. Without `fold`, the scanned table's
// entry offsets[d * groups + g]; with it, from the unscanned digit counts offsets[d * groups + g']:
// the keys of every tile with a lower digit, then those of digit d in tiles before g. Work-item lid
// takes digits [lid * PER, lid * PER + PER). Every work-item calls it either way (its work-group
// scan has barriers: called inside a branch, it corrupted the heap of pocl 3.1's basic device).
#define PER ((RADIX_MAX + WG - 1) / WG)
inline void digit_bases(__global const uint* offsets, const uint fold, const uint radix, const uint groups,
                        const uint g, __local uint* digit_base, __local uint* scratch) {
    const uint lid = get_local_id(0);
    uint totals[PER];
    uint sum = 0;
    for (uint k = 0; k < PER; ++k) {
        const uint d = lid * PER + k;
        uint total = 0, before = 0;
        if (d < radix && !fold) {
            before = offsets[d * groups + g];
        } else if (d < radix) {
            for (uint t = 0; t < groups; ++t) {
                const uint c = offsets[d * groups + t];
                total += c;
                if (t < g) before += c;
            }
        }
        if (d < radix) digit_base[d] = before;
        totals[k] = total;
        sum += total;
    }
    uint all;
    uint prefix = work_group_exclusive_scan(sum, scratch, &all);  // 0 everywhere without fold
    for (uint k = 0; k < PER; ++k) {
        const uint d = lid * PER + k;
        if (d < radix) digit_base[d] += prefix;
        prefix += totals[k];
    }
}

__kernel void sort_scatter(__global const uint* keys_in, const uint keys_in_at, __global const uint* vals_in,
                           const uint vals_in_at, __global uint* keys_out, const uint keys_out_at,
                           __global uint* vals_out, const uint vals_out_at, const uint n, const uint shift,
                           const uint bits, const uint groups, __global const uint* offsets, const uint fold) {
    keys_in += keys_in_at;
    vals_in += vals_in_at;
    keys_out += keys_out_at;
    vals_out += vals_out_at;
    __local uint exch[2 * PADDED_TILE];
    __local uint digit_base[RADIX_MAX];  // where position 0 of the tile would go for each digit
    __local uint scratch[2 * WG];
    const uint lid = get_local_id(0);
    const uint g = get_group_id(0);
    const uint radix = 1u << bits;
    const uint mask = radix - 1u;
    digit_bases(offsets, fold, radix, groups, g, digit_base, scratch);

    const uint base = g * TILE;
    const uint count = min((uint)TILE, n - base);
    uint key[ITEMS], val[ITEMS];
    // Missing pairs of the last tile get the largest digit, so they sort after every real pair.
    load_blocked(keys_in, base, count, 0xffffffffu, key);
    load_blocked(vals_in, base, count, 0u, val);

    // Sort the tile by the digit, 4 bits at a time from the lowest (each step is stable).
    for (uint s = 0; s < bits; s += 4) {
        if (s > 0) {
            barrier(CLK_LOCAL_MEM_FENCE);
            for (uint j = 0; j < ITEMS; ++j) {
                const uint p = PAD(lid * ITEMS + j);
                key[j] = exch[p];
                val[j] = exch[PADDED_TILE + p];
            }
        }
        rank_and_exchange(key, val, shift + s, min(4u, bits - s), exch, scratch);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // The first position p of each digit's run in the sorted tile: that run goes to
    // offsets[d, g] onwards, so position p goes to digit_base[d] + p once p is subtracted.
    for (uint j = 0; j < ITEMS; ++j) {
        const uint p = lid + j * WG;
        if (p < count) {
            const uint d = (exch[PAD(p)] >> shift) & mask;
            if (p == 0 || d != ((exch[PAD(p - 1)] >> shift) & mask)) digit_base[d] -= p;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    // Striped writes: consecutive work-items write consecutive positions of a digit's run.
    for (uint j = 0; j < ITEMS; ++j) {
        const uint p = lid + j * WG;
        if (p < count) {
            const uint k = exch[PAD(p)];
            const uint dst = digit_base[(k >> shift) & mask] + p;
            keys_out[dst] = k;
            vals_out[dst] = exch[PADDED_TILE + PAD(p)];
        }
    }
}
