// Inlet buffers (scene/open_boundaries.hpp): every owned fluid particle inside an inlet's box is
// given the inlet's velocity and no acceleration, between the force pass and the kick, so the kick
// keeps that velocity and the next drift moves it by exactly velocity dt. Its density still
// follows the continuity equation (drho/dt in accel.w is kept), as a wall's does.
//   boxes: per inlet 9 floats, min xyz and max xyz relative to the domain's min corner, velocity xyz.
#include "grid.h"

__kernel void impose_inlets(const uint first, const uint last, const GridParams g, const uint inlets,
                            __global const float* boxes, __global const float4* pos, __global const uint* ids,
                            __global float4* velrho, __global float4* accel) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    if ((ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const float4 p = pos[i];
    const uint key = pos_key(p);
    if (key == g.invalid_key) return;
    float3 x;
    S_OF(x) = ((float)key_s(g, key) + 0.5f) * g.cell_s;
    A_OF(x) = ((float)key_a(g, key) + 0.5f) * g.cell_a;
    B_OF(x) = ((float)key_b(g, key) + 0.5f) * g.cell_b;
    x += p.xyz;
    for (uint k = 0u; k < inlets; ++k) {
        __global const float* b = boxes + 9u * k;
        if (x.x >= b[0] && x.y >= b[1] && x.z >= b[2] && x.x < b[3] && x.y < b[4] && x.z < b[5]) {
            const float4 v = velrho[i];
            velrho[i] = (float4)(b[6], b[7], b[8], v.w);
            accel[i] = (float4)(0.0f, 0.0f, 0.0f, accel[i].w);
            return;
        }
    }
}
