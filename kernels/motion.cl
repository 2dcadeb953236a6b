// Prescribed motion of solids (clsph/scene.hpp, Motion; host/src/device/motion_table.hpp): each
// owned boundary particle of a moving solid is put where the motion's closed form has it at the
// step's time, with the closed form's velocity (the force pass reads it: the wall's viscosity and
// the continuity equation; the kick counts it in the CFL speed). In double, from the particle's
// rest position: nothing accumulates over steps. The same formulas as scene/motion.cpp.
//   t = when[0] + fraction when[1]: the time before the step and its dt (the device's clock, or
//   the host's values in `host_when` on the synchronous path).
// The segment of a solid is its last with start <= t; the particle is taken from rest to where
// that segment starts (its start pose), then tau = min(t, end) - start into it; at or after its
// end the solid rests there.
// Devices without cl_khr_fp64 (CLSPH_MOTION_FLOAT) evaluate it in float, from float tables and the
// host's time (they have no clock, so no step ahead either).
#include "grid.h"
#ifdef CLSPH_MOTION_FLOAT
typedef float real;
typedef float3 real3;
typedef float4 real4;
#define convert_real3 convert_float3
#else
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
typedef double3 real3;
typedef double4 real4;
#define convert_real3 convert_double3
#endif

#define SEG 28u  // MotionTable::kSegmentDoubles

inline real3 mul_pose(__global const real* r, const real3 u) {
    return (real3)(r[0] * u.x + r[1] * u.y + r[2] * u.z + r[9], r[3] * u.x + r[4] * u.y + r[5] * u.z + r[10],
                     r[6] * u.x + r[7] * u.y + r[8] * u.z + r[11]);
}

// The last segment of `solid` with start <= t, or -1. The table is sorted by (solid, start)
// (device/motion_table.hpp): a binary search for the last row not after (solid, t), so a motion
// from a long CSV file costs log2 of its rows.
inline int segment_at(const uint segments, __global const real* table, const real solid, const real t) {
    uint lo = 0u, hi = segments;
    while (lo < hi) {
        const uint mid = lo + (hi - lo) / 2u;
        __global const real* s = table + mid * SEG;
        if (s[3] < solid || (s[3] == solid && s[1] <= t)) lo = mid + 1u;
        else hi = mid;
    }
    if (lo == 0u || table[(lo - 1u) * SEG + 3] != solid) return -1;
    return (int)lo - 1;
}

// A ramped segment's r(tau) sin(w tau) and its derivative, r = (1 - cos(pi tau / ramp)) / 2 over
// the ramp, then 1 (scene/motion.cpp).
inline real ramped_sine(__global const real* s, const real tau, real* rate) {
    const real w = s[22], ramp = s[25];
    const real pi = (real)3.14159265358979323846;
    real r = (real)1, dr = (real)0;
    if (tau < ramp) {
        r = (real)0.5 * ((real)1 - cos(pi * tau / ramp));
        dr = (real)0.5 * (pi / ramp) * sin(pi * tau / ramp);
    }
    *rate = dr * sin(w * tau) + r * w * cos(w * tau);
    return r * sin(w * tau);
}

// r turned by theta about the unit vector n (Rodrigues).
inline real3 turn(const real3 n, const real theta, const real3 r) {
    const real cs = cos(theta), sn = sin(theta);
    return r * cs + cross(n, r) * sn + n * (dot(n, r) * ((real)1 - cs));
}

// A rotating segment's angle after tau (types 2, 3, 4, 6).
inline real angle_of(__global const real* s, const real tau) {
    const real w = s[22], phase = s[23], mag = s[24];
    if ((int)s[0] == 6) {
        real rate;
        return mag * ramped_sine(s, tau, &rate);
    }
    return (int)s[0] == 2 ? mag * (sin(w * tau + phase) - sin(phase)) : mag * tau;
}

inline bool turns(const int type) { return type == 2 || type == 3 || type == 4 || type == 6; }

__kernel void move_solids(const uint first, const uint last, const GridParams g, __global const real* step_clock,
                          const uint use_clock, const real host_time, const real host_dt, const real fraction,
                          const uint segments, __global const real* table, __global const float4* rest,
                          __global const real4* relative, const uint rest_count, __global float4* pos,
                          __global float4* velrho, __global const uint* ids, __global const uint* halt) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last || *halt != 0u) return;
    const uint word = ids[i];
    if ((word >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) return;
    const uint id = word & CLSPH_ID_MASK;
    if (id >= rest_count) return;
    const real4 l = relative[id];
    if (l.w < 0.0) return;  // a still boundary
    float4 p = pos[i];
    const uint key = pos_key(p);
    if (key == g.invalid_key) return;
    const real t = use_clock ? step_clock[0] + fraction * step_clock[1] : host_time + fraction * host_dt;
    const real3 u0 = l.xyz;
    real3 u = u0, v = (real3)(0.0);
    const int found = segment_at(segments, table, l.w, t);
    if (found >= 0) {
        __global const real* s = table + (uint)found * SEG;
        const int type = (int)s[0];
        const real3 y = mul_pose(s + 4, u0);
        const bool moving = t < s[2];
        const real tau = fmin(t, s[2]) - s[1];
        const real3 vec = (real3)(s[16], s[17], s[18]);
        const real w = s[22], phase = s[23], mag = s[24];
        if (type == 0) {  // linear
            u = y + vec * tau;
            if (moving) v = vec;
        } else if (type == 1) {  // sine
            u = y + vec * (sin(w * tau + phase) - sin(phase));
            if (moving) v = vec * (w * cos(w * tau + phase));
        } else if (type == 5) {  // ramped sine (a piston wave maker)
            real rate;
            u = y + vec * ramped_sine(s, tau, &rate);
            if (moving) v = vec * rate;
        } else if (type == 4) {  // linear_rotation: about the axis through c + velocity tau
            const real3 vel = (real3)(s[25], s[26], s[27]);
            const real3 c = (real3)(s[19], s[20], s[21]) + vel * tau;
            u = c + turn(vec, mag * tau, y - (real3)(s[19], s[20], s[21]));
            if (moving) v = vel + cross(vec * mag, u - c);
        } else {  // rotations: about the unit axis vec through c
            const real3 c = (real3)(s[19], s[20], s[21]);
            real rate = type == 2 ? mag * w * cos(w * tau + phase) : mag;
            if (type == 6) {
                ramped_sine(s, tau, &rate);
                rate *= mag;
            }
            u = c + turn(vec, angle_of(s, tau), y - c);
            if (moving) v = cross(vec * rate, u - c);
        }
    }
    // The new offset from the particle's present cell: its rest offset, the displacement, and the
    // rest cell's place relative to the present one (settled into its cell by the cell pass).
    const float4 r0 = rest[id];
    const uint key0 = as_uint(r0.w);
    const real3 d = u - u0;
    real3 off = convert_real3(r0.xyz);
    real cell[3];
    cell[0] = ((real)((int)key_s(g, key0) - (int)key_s(g, key))) * (real)g.cell_s;
    cell[1] = ((real)((int)key_a(g, key0) - (int)key_a(g, key))) * (real)g.cell_a;
    cell[2] = ((real)((int)key_b(g, key0) - (int)key_b(g, key))) * (real)g.cell_b;
    COMP(off, AXIS_S) += cell[0];
    COMP(off, AXIS_A) += cell[1];
    COMP(off, AXIS_B) += cell[2];
    off += d;
    p.xyz = convert_float3(off);
    pos[i] = p;
    float4 vr = velrho[i];
    vr.xyz = convert_float3(v);
    velrho[i] = vr;
}

// mDBC: the ghost-node offsets of the owned boundary particles of moving solids turned as their
// solid has turned by time t (the same t as move_solids' last put them): ghost[id] = R(t)
// ghost_rest[id]. Run before each mDBC pass on the particles it evaluates (those owned after the
// exchange), so the offsets are the formula's wherever a particle has moved to.
__kernel void turn_ghost_nodes(const uint first, const uint last, __global const real* step_clock, const uint use_clock,
                               const real host_time, const real host_dt, const real fraction, const uint segments,
                               __global const real* table, __global const real4* relative, const uint rest_count,
                               __global const float4* ghost_rest, __global float4* ghost, __global const uint* ids,
                               __global const uint* halt) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last || *halt != 0u) return;
    const uint word = ids[i];
    if ((word >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) return;
    const uint id = word & CLSPH_ID_MASK;
    if (id >= rest_count) return;
    const real solid = relative[id].w;
    if (solid < 0) return;
    const real t = use_clock ? step_clock[0] + fraction * step_clock[1] : host_time + fraction * host_dt;
    const float4 g0 = ghost_rest[id];
    real3 g = convert_real3(g0.xyz);
    const int found = segment_at(segments, table, solid, t);
    if (found >= 0) {
        __global const real* s = table + (uint)found * SEG;
        g = (real3)(s[4] * g.x + s[5] * g.y + s[6] * g.z, s[7] * g.x + s[8] * g.y + s[9] * g.z,
                    s[10] * g.x + s[11] * g.y + s[12] * g.z);
        if (turns((int)s[0])) g = turn((real3)(s[16], s[17], s[18]), angle_of(s, fmin(t, s[2]) - s[1]), g);
    }
    float4 out = g0;
    out.xyz = convert_float3(g);
    ghost[id] = out;
}
