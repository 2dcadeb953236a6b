// The tiled interaction scheme's work list (neighbour_loop.h): per non-empty cell, how many chunks
// of at most 32 particles its owned particles make; an exclusive scan of these gives chunk_start.
__kernel void chunk_counts(const uint cells, const uint first, const uint last, __global const uint* cell_start,
                           __global uint* counts) {
    const uint c = get_global_id(0);
    if (c >= cells) return;
    const uint b = clamp(cell_start[c], first, last), e = clamp(cell_start[c + 1u], first, last);
    counts[c] = (e - b + 31u) / 32u;
}
