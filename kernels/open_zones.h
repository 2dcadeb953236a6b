// What the open boundaries' kernels (inlets.cl, outlets.cl) share: a particle's position relative
// to the domain's min corner from its cell and offset, and a component by a run-time axis.
#ifndef CLSPH_OPEN_ZONES_H
#define CLSPH_OPEN_ZONES_H
#include "grid.h"

inline float3 absolute_position(const GridParams g, const float4 p, const uint key) {
    float3 x;
    S_OF(x) = ((float)key_s(g, key) + 0.5f) * g.cell_s;
    A_OF(x) = ((float)key_a(g, key) + 0.5f) * g.cell_a;
    B_OF(x) = ((float)key_b(g, key) + 0.5f) * g.cell_b;
    return x + p.xyz;
}

inline float component(const float3 x, const uint axis) { return axis == 0u ? x.x : axis == 1u ? x.y : x.z; }

#endif
