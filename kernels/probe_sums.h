// SPH interpolation at an arbitrary point x (given like a particle: offset from its cell centre,
// key bits in w) from the fluid particles j within the support: (sum V_j W, sum p_j V_j W),
// V_j = m / rho_j. Shared by the probes (probes.cl) and the free surface's field (surface.cl).
#ifndef CLSPH_PROBE_SUMS_H
#define CLSPH_PROBE_SUMS_H
#include "grid.h"
#include "sph_kernel.h"

inline float2 probe_sums_at(const float4 x, const uint cells, const GridParams g, const SphParams sp,
                            __global const uint* cell_key, __global const uint* cell_start,
                            __global const float4* pos, __global const float4* velrho, __global const uint* ids) {
    const uint key = pos_key(x);
    float2 sums = (float2)(0.0f);
    if (key != g.invalid_key) {
        const int s = (int)key_s(g, key), a = (int)key_a(g, key);
        const uint b = key_b(g, key);
        for (uint r = 0; r < ROWS; ++r) {
            uint begin, end;
            if (row_of_point(g, cells, cell_key, cell_start, s, a, b, r, &begin, &end)) {
                for (uint j = begin; j < end; ++j) {
                    if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
                    const float4 pj = pos[j];
                    const float3 d = relative_position(g, key, x, pos_key(pj), pj);
                    const float r2 = dot(d, d);
                    if (r2 >= sp.support2) continue;
                    const float rho = velrho[j].w;
                    const float vw = sp.mass / rho * kernel_w(&sp, sqrt(r2));
                    sums += (float2)(vw, vw * pressure_of(&sp, rho));
                }
            }
        }
    }
    return sums;
}

#endif
