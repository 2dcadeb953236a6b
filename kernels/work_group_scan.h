// Work-group-wide exclusive scan of one uint per work-item, for the primitives (scan.cl,
// radix_sort.cl). Local memory and barriers only: OpenCL 1.2 has no subgroups, and warp-synchronous
// tricks are unsafe on GPUs that schedule threads of a warp independently (NVIDIA since Volta).
// Needs WG (the work-group size, a power of two) defined at build time.
#ifndef CLSPH_WORK_GROUP_SCAN_H
#define CLSPH_WORK_GROUP_SCAN_H

// Returns x[0] + ... + x[lid-1] over the work-group and stores the sum of all x in *total.
// `scratch` holds 2 * WG uints. Every work-item must call it (it has barriers); `scratch` may be
// reused as soon as it returns.
inline uint work_group_exclusive_scan(const uint x, __local uint* scratch, uint* total) {
    const uint lid = get_local_id(0);
    // Hillis-Steele with two halves of scratch: reading one half and writing the other needs a
    // single barrier per step instead of two. log2(WG) steps.
    uint from = 0;
    scratch[lid] = x;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint offset = 1; offset < WG; offset <<= 1) {
        uint v = scratch[from + lid];
        if (lid >= offset) v += scratch[from + lid - offset];
        from ^= WG;
        scratch[from + lid] = v;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const uint inclusive = scratch[from + lid];
    *total = scratch[from + WG - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
    return inclusive - x;
}

#endif
