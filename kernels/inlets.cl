// Inlet buffers (scene/open_boundaries.hpp): every owned fluid particle inside an inlet's box is
// given the buffer's velocity, direction * speed * factor (shared.h, InletBox), and no
// acceleration, in both acceleration buffers (`accel` and `accel_new`: the last force pass's and
// this one's; one buffer twice before the drift), so that the kick keeps that velocity and the
// drift moves it by exactly velocity dt. Its density still follows the continuity equation
// (drho/dt in accel.w is kept), as a wall's does. The host launches it twice a step: after the
// force pass with the speed at the step's end, and before the drift with the speed whose dt is the
// buffer's travel over the step (X(t + dt) - X(t)).
#include "open_zones.h"

// In the buffer: along the flow from its upstream face (included: a new layer may lie on it) to
// its downstream one (not: a layer there has left); across it the faces included, as the lattice
// of its section is. Within dp / 1000 at the faces included, for a point on a face that float
// rounds to just outside.
inline bool in_box(const float3 x, __global const InletBox* b) {
    const float tol = 1e-3f / b->inv_dp;
    for (uint k = 0u; k < 3u; ++k) {
        const float c = component(x, k), lo = b->lo[k], hi = b->hi[k], dir = b->direction[k];
        const bool in = dir > 0.0f   ? c >= lo - tol && c < hi
                        : dir < 0.0f ? c > lo && c <= hi + tol
                                     : c >= lo - tol && c <= hi + tol;
        if (!in) return false;
    }
    return true;
}

__kernel void impose_inlets(const uint first, const uint last, const GridParams g, const uint inlets,
                            __global const InletBox* boxes, __global const float* factors,
                            __global const float* speeds, __global const float4* pos, __global const uint* ids,
                            __global float4* velrho, __global float4* accel, __global float4* accel_new) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    if ((ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const float4 p = pos[i];
    const uint key = pos_key(p);
    if (key == g.invalid_key) return;
    const float3 x = absolute_position(g, p, key);
    for (uint k = 0u; k < inlets; ++k) {
        __global const InletBox* b = boxes + k;
        if (!in_box(x, b)) continue;
        float factor = 1.0f;
        if (b->axis < 3u) {
            const int c = (int)round((component(x, b->axis) - b->column0) * b->inv_dp);
            factor = factors[b->first + (uint)clamp(c, 0, (int)b->columns - 1)];
        }
        const float u = speeds[k] * factor;
        const float4 v = velrho[i];
        velrho[i] = (float4)(b->direction[0] * u, b->direction[1] * u, b->direction[2] * u, v.w);
        accel[i] = (float4)(0.0f, 0.0f, 0.0f, accel[i].w);
        accel_new[i] = (float4)(0.0f, 0.0f, 0.0f, accel_new[i].w);
        return;
    }
}
