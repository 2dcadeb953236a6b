// The Morton order within cells (CellOrder::morton, docs/interaction.md): each cell's particles of
// the sorted [0, n) by the sub-cell they lie in, after the last sort or merge of a step. Built only
// where a run asks for that order (CellPipeline::order_within_cells), so a device in arrival order
// never compiles it. 2 levels, 64 sub-cells.
#include "grid.h"

#define CLSPH_ORDER_LEVELS 2
// q = floor(offset * scale) + 2^levels / 2, clamped to the sub-cells of an axis, scale = 2^levels /
// cell in float from the host (CellPipeline::sub_cell_scales): one rounded product and nothing a
// compiler could contract, so the host's tests compute the same codes.
inline uint sub_cell_bits(const float offset, const float scale) {
    const int top = (1 << CLSPH_ORDER_LEVELS) - 1;
    return (uint)clamp((int)floor(offset * scale) + (1 << (CLSPH_ORDER_LEVELS - 1)), 0, top);
}

// Each particle's sub-cell code, into codes[0, n) (the reorder scratch, free until the gathers):
// its sub-cell of the cell it lies in, CLSPH_ORDER_LEVELS halvings per axis, the axes' bits
// interleaved s, a, b from the coarsest level down.
__kernel void sub_cell_codes(const uint n, const float scale_s, const float scale_a, const float scale_b,
                             __global const float4* pos, __global uint* codes) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float4 p = pos[i];
    const uint qs = sub_cell_bits(S_OF(p), scale_s), qa = sub_cell_bits(A_OF(p), scale_a),
               qb = sub_cell_bits(B_OF(p), scale_b);
    // Two levels written out (on pocl 1.01 ms for 265 k particles against the loop's 1.27): s, a, b
    // of the coarse halving, then of the fine one.
    codes[i] = ((qs & 2u) << 4) | ((qa & 2u) << 3) | ((qb & 2u) << 2) | ((qs & 1u) << 2) | ((qa & 1u) << 1) | (qb & 1u);
}

#define CLSPH_SUB_CELLS (1 << (3 * CLSPH_ORDER_LEVELS))

// The order that sorts each cell's particles of the sorted [0, n) by (sub-cell code, index), the
// cells themselves left where they are: order[j] = the particle that goes to j (for gather_*). The
// work-item of a cell's first particle counts its codes and places them (a stable counting sort,
// O(m + sub-cells) for a cell of m). A pure function of each cell's particles in their order, so
// devices holding the same cell in the same order (any device count) give it the same order.
__kernel void order_within_cells(const uint n, __global const uint* keys, __global const uint* codes,
                                 __global uint* order) {
    const uint first = get_global_id(0);
    if (first >= n || (first > 0u && keys[first - 1u] == keys[first])) return;
    const uint key = keys[first];
    uint end = first + 1u;
    while (end < n && keys[end] == key) ++end;
    if (end - first == 1u) {
        order[first] = first;
        return;
    }
    uint at[CLSPH_SUB_CELLS];
    for (uint c = 0; c < CLSPH_SUB_CELLS; ++c) at[c] = 0u;
    for (uint j = first; j < end; ++j) ++at[codes[j]];
    uint sum = first;
    for (uint c = 0; c < CLSPH_SUB_CELLS; ++c) {
        const uint k = at[c];
        at[c] = sum;
        sum += k;
    }
    for (uint j = first; j < end; ++j) order[at[codes[j]]++] = j;
}
