// Thinned downloads (clsph run --output-stride, --output-box): the owned particles whose id is
// divisible by `stride` (and whose cell meets a box), packed on the device so that only they cross to the host (host/src/device/thin_download.cpp).
#include "shared.h"

// Kept: the id is divisible by `stride` and the particle's cell lies in the cell box
// [lo, hi] (per key position s, a, b: the cells a box of space overlaps; the host then keeps the
// particles inside the box itself). Particles outside the domain (the invalid key) never.
__kernel void stride_flags(const uint n, const uint first, const uint stride, const uint4 lo, const uint4 hi,
                           const uint shift_s, const uint shift_a, const uint mask_a, const uint mask_b,
                           const uint reach, const uint invalid_key, __global const uint* ids,
                           __global const float4* pos, __global uint* flags) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    const uint key = as_uint(pos[first + g].w);
    const uint s = shift_s >= 32u ? 0u : key >> shift_s, a = (key >> shift_a) & mask_a, b = (key & mask_b) - reach;
    const bool in = key != invalid_key && s >= lo.x && s <= hi.x && a >= lo.y && a <= hi.y && b >= lo.z && b <= hi.z;
    flags[g] = in && (ids[first + g] & CLSPH_ID_MASK) % stride == 0u ? 1u : 0u;
}

// The kept particles at their ranks, in the store's order.
// rank: the exclusive scan of the flags (rank[g + 1] > rank[g]: kept).
__kernel void stride_gather(const uint n, const uint first, __global const uint* ids, __global const uint* rank,
                            __global const float4* pos, __global const float4* velrho, __global float4* out_pos,
                            __global float4* out_velrho, __global uint* out_id) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    const uint k = rank[g];
    if (rank[g + 1] == k) return;
    const uint id = ids[first + g];
    out_pos[k] = pos[first + g];
    out_velrho[k] = velrho[first + g];
    out_id[k] = id;
}
