// For the tests only (tests/device/test_physics.cpp): W and grad W at given offsets from a particle.
#include "shared.h"
#include "sph_kernel.h"

__kernel void kernel_values(const uint n, const SphParams sp, __global const float4* offsets, __global float4* out) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float3 d = offsets[i].xyz;  // x_i - x_j
    const float r = length(d);
    const float f = kernel_f(&sp, r);
    out[i] = (float4)(f * d, kernel_w(&sp, r));
}
