// The cell pipeline of one device: cell keys, reorder, compaction of non-empty cells, and each
// cell's 9 neighbour rows as particle ranges. See host/src/device/cell_pipeline.cpp for the order.
#include "settle.h"

// Each particle's offset is brought back inside its cell (the drift may have carried it out), its
// key recomputed and written to pos.w and keys[]; vals[] = i for the sort. Outside the domain:
// invalid_key, so the sort moves it to the end where it is removed and counted.
// Particles outside [keep_first, keep_end) are being dropped (stale ghosts, particles that moved to
// another device): they get invalid_key too, without touching their data.
// Several devices, one sort per step: particles from tail_first on (arrivals) are all kept, and a
// particle in [keep_first, keep_end) only while its key lies in [key_lo, key_hi) (the columns this
// device needs); one device: tail_first = n, [key_lo, key_hi) = [0, invalid_key).
__kernel void cell_keys(const uint n, const uint keep_first, const uint keep_end, const uint tail_first,
                        const uint key_lo, const uint key_hi, const uint settle, const GridParams g, __global float4* pos,
                        __global uint* keys, __global uint* vals) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float4 p = pos[i];
    uint key = pos_key(p);
    if ((i < keep_first || i >= keep_end) && i < tail_first) {
        key = g.invalid_key;
    } else if (key != g.invalid_key && !settle) {
        // Settled already (settle_owned, or by the device that sent it).
        if (i < tail_first && (key < key_lo || key >= key_hi)) key = g.invalid_key;
    } else if (key != g.invalid_key) {
        uint s = key_s(g, key), a = key_a(g, key), b = key_b(g, key);
        float os = S_OF(p), oa = A_OF(p), ob = B_OF(p);
        const bool inside = settle_axis(&os, &s, g.cell_s, g.n_s, g.ext_s, 0u) &&
                            settle_axis(&oa, &a, g.cell_a, g.n_a, g.ext_a, g.periodic_a) &&
                            settle_axis(&ob, &b, g.cell_b, g.n_b, g.ext_b, 0u);
        key = inside ? make_key(g, s, a, b) : g.invalid_key;
        S_OF(p) = os;
        A_OF(p) = oa;
        B_OF(p) = ob;
        p.w = as_float(key);
        pos[i] = p;
        if (i < tail_first && (key < key_lo || key >= key_hi)) key = g.invalid_key;  // not needed here
    }
    keys[i] = key;
    vals[i] = i;
}

// Several devices, before the exchange: the owned particles' drifted positions settled into their
// cells (new key in pos.w, nothing sorted). counters[0] counts particles that left the domain,
// counters[1] those that moved more than one column (the exchange then cannot trust that a column
// holds only particles from its old neighbours, and sorts first), counters[2] those now in
// [key_lo, key_hi) (the columns this device keeps), counters[3] and [4] those of them with keys
// below split_lo and below split_hi (the interior whose forces run while the arrivals travel
// starts and ends there among the kept particles sorted: multi/exchange.cpp; 0, 0: none).
__kernel void settle_owned(const uint first, const uint end, const uint key_lo, const uint key_hi,
                           const uint split_lo, const uint split_hi, const GridParams g, __global float4* pos,
                           __global uint* counters) {
    __local uint local_counts[5];
    begin_counts(local_counts, 5u);
    const uint i = first + (uint)get_global_id(0);
    if (i < end) {
        const uint key = settle_particle(i, key_lo, key_hi, g, pos, local_counts);
        if (key >= key_lo && key < key_hi && key != g.invalid_key) {
            if (key < split_lo) atomic_inc(&local_counts[3]);
            if (key < split_hi) atomic_inc(&local_counts[4]);
        }
    }
    end_counts(local_counts, counters, 5u);
}

// The step ahead on one device, three launches in one (issue 30): drift_settle_key (settle.h) for
// each particle of [0, n). Where the sort can borrow the reorder scratch, drift_histogram.cl's
// kernel does this with the sort's first digit counts besides.
__kernel void drift_settle_keys(const uint n, const uint first, const uint end, const uint key_lo, const uint key_hi,
                                const GridParams g, __global const float* dt_f, const float rho0,
                                __global float4* pos, __global float4* velrho, __global const float4* accel,
                                __global const uint* ids, __global const uint* halt, __global uint* counters,
                                __global uint* keys, __global uint* vals) {
    __local uint local_counts[3];
    begin_counts(local_counts, 3u);
    const uint i = get_global_id(0);
    if (i < n) {
        keys[i] = drift_settle_key(i, first, end, key_lo, key_hi, g, dt_f[0], rho0, pos, velrho, accel, ids, halt,
                                   local_counts);
        vals[i] = i;
    }
    end_counts(local_counts, counters, 3u);
}

// flags[i - first] = 1 for particles of [first, end) whose key lies in [key_lo, key_hi).
__kernel void flag_key_range(const uint first, const uint end, const uint key_lo, const uint key_hi,
                             __global const float4* pos, __global uint* flags) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= end) return;
    const uint key = pos_key(pos[i]);
    flags[i - first] = key >= key_lo && key < key_hi;
}

// An edge's particles in sorted order (order[j]: where entry j comes from) into four regions of
// the scratch buffer, m entries each: positions, velocity+density, acceleration, ids.
__kernel void edge_gather(const uint m, __global const uint* order, __global const float4* pos,
                          __global const float4* velrho, __global const float4* accel, __global const uint* id,
                          __global float4* scratch) {
    const uint j = get_global_id(0);
    if (j >= m) return;
    const uint i = order[j];
    scratch[j] = pos[i];
    scratch[m + j] = velrho[i];
    scratch[2u * m + j] = accel[i];
    ((__global uint*)(scratch + 3u * m))[j] = id[i];
}

// And back into place: entries [0, kept) to particles [first, first + kept) (the rest, dropped
// keys, sorted last, stay out).
__kernel void edge_place(const uint m, const uint first, const uint kept, __global const float4* scratch,
                         __global float4* pos, __global float4* velrho, __global float4* accel, __global uint* id) {
    const uint j = get_global_id(0);
    if (j >= kept) return;
    const uint i = first + j;
    pos[i] = scratch[j];
    velrho[i] = scratch[m + j];
    accel[i] = scratch[2u * m + j];
    id[i] = ((__global const uint*)(scratch + 3u * m))[j];
}

// The flagged particles (after the exclusive scan of the flags: their rank) copied, in order, to
// out_*[base + rank]: a packed block that is then read to the host in four transfers.
__kernel void gather_key_range(const uint first, const uint end, const uint key_lo, const uint key_hi,
                               const uint base, __global const uint* rank, __global const float4* pos,
                               __global const float4* velrho, __global const float4* accel, __global const uint* id,
                               __global float4* out_pos, __global float4* out_velrho, __global float4* out_accel,
                               __global uint* out_id) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= end) return;
    const float4 p = pos[i];
    const uint key = pos_key(p);
    if (key < key_lo || key >= key_hi) return;
    const uint o = base + rank[i - first];
    out_pos[o] = p;
    out_velrho[o] = velrho[i];
    out_accel[o] = accel[i];
    out_id[o] = id[i];
}

// dst[i] = src[order[i]]: one particle array into sorted order (through the rotating scratch).
__kernel void gather_float4(const uint n, const uint dst_offset, __global const uint* order,
                            __global const float4* src, __global float4* dst) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    dst[dst_offset + i] = src[order[i]];
}

__kernel void gather_uint(const uint n, const uint dst_offset, __global const uint* order, __global const uint* src,
                          __global uint* dst) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    dst[dst_offset + i] = src[order[i]];
}

// One edge of an almost sorted array, for a small sort of its own (several devices: what arrived
// from the neighbours was placed before and after the sorted particles this device kept). Entry j
// of [0, count) stands for particle i = first + j: keys[j] = its sort code, vals[j] = i. Particles
// [drop_first, drop_end) are the ones the sort before dropped (stale ghosts keep an old key in
// pos.w) and keys outside [key_lo, key_hi) are no longer needed here: both sort last. The code is
// the key clamped to [code_lo, code_hi], less code_lo: the edge's keys differ only in a few columns
// (the split axis is the key's top part), so the sort runs over the few bits that vary. Clamping
// keeps the stable order because only particles kept in sorted order lie beyond the clamps
// (CellPipeline::enqueue_edge_sort).
__kernel void edge_keys(const uint first, const uint count, const uint drop_first, const uint drop_end,
                        const uint key_lo, const uint key_hi, const uint code_lo, const uint code_hi,
                        __global const float4* pos, __global uint* keys, __global uint* vals) {
    const uint j = get_global_id(0);
    if (j >= count) return;
    const uint i = first + j;
    const uint key = pos_key(pos[i]);
    const bool valid = (i < drop_first || i >= drop_end) && key >= key_lo && key < key_hi;
    keys[j] = valid ? clamp(key, code_lo, code_hi) - code_lo : code_hi - code_lo + 1u;
    vals[j] = i;
}

// The sort input of a device whose edges cannot be sorted alone (a slab too narrow for them, or
// no column positions yet): in memory the particles it held, [0, held), then the arrivals, left
// ones first; taken in the order [left arrivals | held | right arrivals], the order one device
// would hold them in, so the stable sort leaves every cell in the canonical order. Held particles
// outside [keep_first, keep_end) (stale ghosts) or with a key outside [key_lo, key_hi) get
// invalid_key; arrivals are all kept. vals[j] = where entry j lives.
__kernel void arrival_keys(const uint held, const uint left, const uint right, const uint keep_first,
                           const uint keep_end, const uint key_lo, const uint key_hi, const uint invalid_key,
                           __global const float4* pos, __global uint* keys, __global uint* vals) {
    const uint j = get_global_id(0);
    if (j >= held + left + right) return;
    const bool arrival = j < left || j >= left + held;
    const uint i = j < left ? held + j : (j < left + held ? j - left : j);
    uint key = pos_key(pos[i]);
    if (!arrival && (i < keep_first || i >= keep_end || key < key_lo || key >= key_hi)) key = invalid_key;
    keys[j] = key;
    vals[j] = i;
}

inline uint starts_cell(__global const uint* keys, const uint i) { return i == 0u || keys[i] != keys[i - 1u]; }

// flags[i] = 1 where a new key begins (all keys in [0, n) are valid cell keys).
__kernel void flag_cells(const uint n, __global const uint* keys, __global uint* flags) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    flags[i] = starts_cell(keys, i);
}

// out[t] = first index in the sorted keys[0, n) whose key is >= thresholds[t] (lower bound): where
// particles outside the domain begin, where a device's slab begins and ends, its edge columns.
__kernel void locate_keys(const uint count, const uint n, __global const uint* keys,
                          __global const uint* thresholds, __global uint* out) {
    const uint t = get_global_id(0);
    if (t >= count) return;
    out[t] = lower_bound_key(keys, n, thresholds[t]);
}

// After the exclusive scan of the flags (K = scan[n] cells), particle i < n's part of the tables:
// cell_key[c], cell_start[c] where it starts a non-empty cell, cell_start[K] = n from the last
// particle, and scan[i] rewritten in place as its cell index (each work-item reads scan[i] before
// it rewrites it, and scan[n] is never rewritten). Cells beyond the tables' capacity `cap` are not
// written.
inline void scatter_cell(const uint i, const uint n, const uint cap, const uint k, __global const uint* keys,
                         __global uint* scan, __global uint* cell_key, __global uint* cell_start) {
    const uint c = scan[i];
    const uint first = starts_cell(keys, i);
    if (first && c < cap) {
        cell_key[c] = keys[i];
        cell_start[c] = i;
    }
    if (i == n - 1u && k <= cap) cell_start[k] = n;
    scan[i] = c + first - 1u;
}

// The tables and each particle's cell in one launch over the particles, the count read back.
__kernel void scatter_cells(const uint n, const uint cap, __global const uint* keys, __global uint* scan,
                            __global uint* cell_key, __global uint* cell_start) {
    const uint i = get_global_id(0);
    if (i < n) scatter_cell(i, n, cap, scan[n], keys, scan, cell_key, cell_start);
}

// The step ahead (no count read back): scatter_cells' work over max(n, cap + 1), with the tables
// holding `cap` cells (every launch over cells runs over all of them). The count K = scan[n] goes to
// count[0] (at most cap: what the tables hold) and count[1] (as found); cells K+1..cap start at n,
// so that a cell beyond K is empty to every loop. K > cap halts the step (step_clock.cl): the host
// grows the tables and redoes it. Tables that overflowed stay safe to read, for a pass that runs
// before anyone looks at the flag (the interior's forces of the halo overlap, whose results are
// then dropped): the last cell they hold ends at n, and a particle of a cell beyond them is given
// that last cell, so every range and index stays inside the arrays.
__kernel void tables_bounded(const uint n, const uint cap, __global const uint* keys, __global uint* scan,
                             __global uint* cell_key, __global uint* cell_start, __global uint* count,
                             __global uint* halt) {
    const uint i = get_global_id(0);
    const uint k = scan[n];
    if (i == 0u) {
        count[0] = min(k, cap);
        count[1] = k;
        if (k > cap) atomic_or(halt, 4u);
    }
    if (i > k && i <= cap) cell_start[i] = n;
    if (i == cap && k > cap) cell_start[cap] = n;
    if (i < n) {
        scatter_cell(i, n, cap, k, keys, scan, cell_key, cell_start);
        if (k > cap && scan[i] >= cap) scan[i] = cap - 1u;
    }
}

// ranges[c * ROWS + r] = [begin, end) of the particles in neighbour row r of cell c (grid.h: the
// cells b - REACH .. b + REACH at one (s + ds, a + da)): consecutive keys thanks to the padding of
// b, hence one contiguous particle range. Rows off the domain are empty; axis a wraps if periodic.
inline void cell_ranges(const uint c, const uint k, const GridParams g, __global const uint* cell_key,
                        __global const uint* cell_start, __global uint2* ranges) {
    const uint key = cell_key[c];
    const int s = (int)key_s(g, key), a = (int)key_a(g, key);
    const uint b = key_b(g, key);
    for (uint r = 0; r < ROWS; ++r) {
        int s2 = s + row_ds(r), a2 = a + row_da(r);
        if (g.periodic_a) {
            if (a2 < 0) a2 += (int)g.n_a;
            if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
        }
        uint2 range = (uint2)(0u, 0u);
        if (s2 >= 0 && s2 < (int)g.n_s && a2 >= 0 && a2 < (int)g.n_a) {
            const uint mid = make_key(g, (uint)s2, (uint)a2, b);
            const uint first = lower_bound_key(cell_key, k, mid - CLSPH_REACH);
            // The row's end: at most 2 REACH + 1 non-empty cells on (the keys are unique), so a
            // few steps rather than a second binary search (half this kernel's time on pocl).
            uint last = first;
            while (last < k && cell_key[last] <= mid + CLSPH_REACH) ++last;
            range = (uint2)(cell_start[first], cell_start[last]);
        }
        ranges[c * ROWS + r] = range;
    }
}

__kernel void neighbour_ranges(const uint k, const GridParams g, __global const uint* cell_key,
                               __global const uint* cell_start, __global uint2* ranges) {
    const uint c = get_global_id(0);
    if (c < k) cell_ranges(c, k, g, cell_key, cell_start, ranges);
}

// The step ahead: launched over the tables' capacity, the count read from count[0]; the cells
// beyond it get empty rows.
__kernel void neighbour_ranges_bounded(const uint cap, const GridParams g, __global const uint* count,
                                       __global const uint* cell_key, __global const uint* cell_start,
                                       __global uint2* ranges) {
    const uint c = get_global_id(0);
    if (c >= cap) return;
    const uint k = count[0];
    if (c < k) {
        cell_ranges(c, k, g, cell_key, cell_start, ranges);
    } else {
        for (uint r = 0; r < ROWS; ++r) ranges[c * ROWS + r] = (uint2)(0u, 0u);
    }
}
