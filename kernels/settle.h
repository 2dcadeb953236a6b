// Settling a drifted offset back into its cell, shared by the cell pipeline (kernels/cells.cl)
// and the step ahead's first launch with the sort's first digit counts (kernels/drift_histogram.cl).
#ifndef CLSPH_SETTLE_H
#define CLSPH_SETTLE_H
#include "advance.h"
#include "grid.h"

// Moves one axis' offset back into [-cell/2, cell/2] by changing the cell; returns false when the
// particle leaves the domain along that axis. Idempotent: an offset already inside (faces
// included) is left alone, so settling twice gives what settling once does. (With the rounded
// quotient alone, an offset at +cell/2 moved to the next cell, landed a rounding below -cell/2
// and moved back the next time: one device and several, which settle a different number of
// times, then disagreed in the last bit.) After a move by one cell the new offset is exact
// (Sterbenz), so it lies inside.
inline bool settle_axis(float* offset, uint* cell, const float cell_size, const uint count, const float extent,
                        const uint periodic) {
    const float half_cell = 0.5f * cell_size;
    const float shift = (*offset > half_cell || *offset < -half_cell) ? floor(*offset / cell_size + 0.5f) : 0.0f;
    int c = (int)(*cell) + (int)shift;
    *offset -= shift * cell_size;
    if (periodic) {
        c %= (int)count;
        if (c < 0) c += (int)count;
    } else {
        if (c < 0 || c >= (int)count) return false;
        // The last cell may stick out past the domain's max face: that part is outside too.
        if (((float)c + 0.5f) * cell_size + *offset > extent) return false;
        if (((float)c + 0.5f) * cell_size + *offset < 0.0f) return false;
    }
    *cell = (uint)c;
    return true;
}

// Particle i settled (settle_owned) and counted in the work-group's local_counts; returns its key.
inline uint settle_particle(const uint i, const uint key_lo, const uint key_hi, const GridParams g, __global float4* pos,
                            __local uint* local_counts) {
    float4 p = pos[i];
    const uint old = pos_key(p);
    if (old == g.invalid_key) return old;
    uint s = key_s(g, old), a = key_a(g, old), b = key_b(g, old);
    float os = S_OF(p), oa = A_OF(p), ob = B_OF(p);
    const bool inside = settle_axis(&os, &s, g.cell_s, g.n_s, g.ext_s, 0u) &&
                        settle_axis(&oa, &a, g.cell_a, g.n_a, g.ext_a, g.periodic_a) &&
                        settle_axis(&ob, &b, g.cell_b, g.n_b, g.ext_b, 0u);
    const uint key = inside ? make_key(g, s, a, b) : g.invalid_key;
    S_OF(p) = os;
    A_OF(p) = oa;
    B_OF(p) = ob;
    p.w = as_float(key);
    pos[i] = p;
    if (!inside) atomic_inc(&local_counts[0]);
    else if (abs((int)s - (int)key_s(g, old)) > 1) atomic_inc(&local_counts[1]);
    if (inside && key >= key_lo && key < key_hi) atomic_inc(&local_counts[2]);
    return key;
}

// Counted per work-group in local memory, then one global atomic per group and counter: one
// global counter hit by every particle serialised the kernel (0.34 ms for 11.7 M particles on an
// H200, 4.5x the cost of cells.keys).
// `count` counters, whatever the work-group's size.
inline void begin_counts(__local uint* local_counts, const uint count) {
    for (uint c = get_local_id(0); c < count; c += get_local_size(0)) local_counts[c] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
}

inline void end_counts(__local uint* local_counts, __global uint* counters, const uint count) {
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint c = get_local_id(0); c < count; c += get_local_size(0))
        if (local_counts[c] != 0u) atomic_add(&counters[c], local_counts[c]);
}

// The step ahead's first launch, for particle i of the sort of [0, n) (issue 30): the first kick
// and drift of an owned particle (integrate.cl, kick_drift), its offset settled with settle_owned's
// counts, and the key cell_keys gives without settling (an owned particle's key if it lies in
// [key_lo, key_hi), else the invalid key). Each step touches only particle i, so doing them in
// turn is the three launches, bitwise.
inline uint drift_settle_key(const uint i, const uint first, const uint end, const uint key_lo, const uint key_hi,
                             const GridParams g, const float dt, const float rho0, __global float4* pos,
                             __global float4* velrho, __global const float4* accel, __global const uint* ids,
                             __global const uint* halt, __local uint* local_counts) {
    if (i < first || i >= end) return g.invalid_key;
    advance(i, end, dt, dt, 0.5f * dt, rho0, g.invalid_key, pos, velrho, accel, ids, halt);
    const uint key = settle_particle(i, key_lo, key_hi, g, pos, local_counts);
    return key < key_lo || key >= key_hi ? g.invalid_key : key;
}

#endif
