// Stream compaction's last step: with offsets = exclusive scan of (flags != 0), every kept element
// moves to its offset. Kept elements keep their order because the scan is monotonic.
__kernel void compact_scatter(__global const uint* flags, __global const uint* values,
                              __global const uint* offsets, __global uint* out, const uint n) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    if (flags[i] != 0u) out[offsets[i]] = values[i];
}
