// Outlet zones (docs/scenes.md, outlets; shared.h, OutletZone), boxes relative to the domain's min
// corner, for owned fluid particles.
#include "open_zones.h"

// After the force pass: a particle in a zone that holds a pressure gets the density Tait's
// equation gives for it (hold 1: the host's, for a constant pressure; hold 2: p = rho0 g (level -
// z), not below 0, rho = rho0 (1 + p / B)^(1/gamma)), and no drho/dt in either acceleration buffer,
// so the kick keeps it and the next drift's prediction too. Its velocity is left to the flow.
__kernel void hold_outlets(const uint first, const uint last, const GridParams g, const uint zones,
                           __global const OutletZone* zone, const float rho0, const float rho0_g, const float inv_b,
                           const float inv_gamma, __global const float4* pos, __global const uint* ids,
                           __global float4* velrho, __global float4* accel, __global float4* accel_new) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    if ((ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const float4 p = pos[i];
    const uint key = pos_key(p);
    if (key == g.invalid_key) return;
    const float3 x = absolute_position(g, p, key);
    for (uint k = 0u; k < zones; ++k) {
        __global const OutletZone* z = zone + k;
        if (z->hold == 0u) continue;
        if (!(x.x >= z->lo[0] && x.y >= z->lo[1] && x.z >= z->lo[2] && x.x < z->hi[0] && x.y < z->hi[1] && x.z < z->hi[2]))
            continue;
        float rho = z->value;
        if (z->hold == 2u) rho = rho0 * pow(1.0f + fmax(0.0f, rho0_g * (z->value - x.z)) * inv_b, inv_gamma);
        velrho[i].w = rho;
        accel[i].w = 0.0f;
        accel_new[i].w = 0.0f;
        return;
    }
}

// After the drift, before the exchange settles the particles into cells: a fluid particle past a
// zone's face (at or beyond its max face along `axis` when `upper`, below its min face otherwise)
// within the zone's extent along the other two axes is removed as one that left the domain is: its
// offset along the split axis is put a whole domain beyond its cell, so the settle (kernels/cells.cl)
// gives it the invalid key and counts it with those that left the domain. Only that one particle's
// position is read, so the removals are the same on any number of devices.
__kernel void remove_past_outlets(const uint first, const uint last, const GridParams g, const uint zones,
                                  __global const OutletZone* zone, __global float4* pos, __global const uint* ids) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    if ((ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    float4 p = pos[i];
    const uint key = pos_key(p);
    if (key == g.invalid_key) return;
    const float3 x = absolute_position(g, p, key);
    for (uint k = 0u; k < zones; ++k) {
        __global const OutletZone* z = zone + k;
        const uint a = (z->axis + 1u) % 3u, b = (z->axis + 2u) % 3u;
        const float xa = component(x, a), xb = component(x, b), along = component(x, z->axis);
        if (xa < z->lo[a] || xa >= z->hi[a] || xb < z->lo[b] || xb >= z->hi[b]) continue;
        if (z->upper ? along < z->hi[z->axis] : along >= z->lo[z->axis]) continue;
        S_OF(p) = (float)(g.n_s + 1u) * g.cell_s;
        pos[i] = p;
        return;
    }
}
