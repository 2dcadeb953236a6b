// Thinned downloads (clsph run --output-stride): the owned particles whose id is divisible by
// `stride`, packed on the device so that only they cross to the host (host/src/device/thin_download.cpp).
#include "shared.h"

__kernel void stride_flags(const uint n, const uint first, const uint stride, __global const uint* ids,
                           __global uint* flags) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    flags[g] = (ids[first + g] & CLSPH_ID_MASK) % stride == 0u ? 1u : 0u;
}

// rank: the exclusive scan of the flags; the kept particles at their ranks, in the store's order.
__kernel void stride_gather(const uint n, const uint first, const uint stride, __global const uint* ids,
                            __global const uint* rank, __global const float4* pos, __global const float4* velrho,
                            __global float4* out_pos, __global float4* out_velrho, __global uint* out_id) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    const uint id = ids[first + g];
    if ((id & CLSPH_ID_MASK) % stride != 0u) return;
    const uint k = rank[g];
    out_pos[k] = pos[first + g];
    out_velrho[k] = velrho[first + g];
    out_id[k] = id;
}
