// How large each device buffer is, in one place: the allocations (particle_store.cpp,
// cell_pipeline.cpp, multi/exchange.cpp, physics.cpp, the primitives' tiles) and the memory plan
// (memory_plan*.cpp) both call these, so the plan cannot drift from what the devices allocate.
// Pure C++: no OpenCL type, nothing but sizes.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace clsph::device::sizing {

inline constexpr std::size_t kUint = 4;     // cl_uint
inline constexpr std::size_t kFloat4 = 16;  // cl_float4
// A particle on a device: position, velocity+density, acceleration+drho/dt (float4 each) and id.
inline constexpr std::size_t kParticleBytes = 3 * kFloat4 + kUint;
// The step ahead's record of one step (device::StepRecord), in doubles.
inline constexpr std::size_t kStepRecordDoubles = 17;
// The step clock's doubles (physics.cpp, with cl_khr_fp64 only).
inline constexpr std::size_t kClockDoubles = 5;
// Floats per kick reduction group (physics.cpp).
inline constexpr std::size_t kKickFloats = 4;
// Digits of the cell sort's radix passes (RadixSort::Config::digit_bits).
inline constexpr unsigned kDigitBits = 8;

// A particle store grown to hold n particles: n (1 + headroom) + 1 (particle_store.cpp reserve()).
inline std::size_t grown_capacity(std::size_t n, double headroom) {
    return static_cast<std::size_t>(static_cast<double>(n) * (1.0 + headroom)) + 1;
}

// A slab's store at the start: every particle on one slab; on several, an even share with the
// headroom (multi/slab_driver.cpp set_up()). At least 1.
inline std::size_t slab_capacity(std::size_t total, std::size_t slabs, double headroom) {
    const std::size_t cap = slabs <= 1 ? total
                                       : static_cast<std::size_t>(static_cast<double>(total) /
                                                                  static_cast<double>(slabs) * (1.0 + headroom));
    return std::max<std::size_t>(cap, 1);
}

// The cell tables for `cells` non-empty cells: the cell headroom and 16 more
// (cell_pipeline.cpp reserve_cells()).
// The settle's counters (cell_pipeline.hpp Settled, kernels/cells.cl settle_owned).
inline constexpr std::size_t kSettleCounters = 5;

inline std::size_t cell_capacity(std::size_t cells, double cell_headroom) {
    return cells + static_cast<std::size_t>(static_cast<double>(cells) * cell_headroom) + 16;
}

// The clusters interaction form (cluster_list.cpp, kernels/clusters.cl): particles per cluster, the
// cluster indices the lists need for a store of `particles` and tables of `cells` (cells +
// particles / size and the end sentinel), the bits of a row's mask (reach 1: rows of three
// support-wide cells need 64) and the bytes of each index: the first particle, the bounding box
// (two float4) and one mask per neighbour row.
inline constexpr std::size_t kClusterSize = 4;
inline std::size_t cluster_indices(std::size_t particles, std::size_t cells) {
    return cells + particles / kClusterSize + 2;
}
inline std::size_t cluster_mask_bits(int reach) { return reach == 1 ? 64 : 32; }
inline std::size_t cluster_begin_bytes(std::size_t indices) { return indices * kUint; }
inline std::size_t cluster_box_bytes(std::size_t indices) { return indices * 2 * kFloat4; }
// The boxes live only while the lists are built: in the store's reorder scratch (free then)
// where they fit, else in a buffer of their own.
inline bool cluster_boxes_borrowed(std::size_t indices, std::size_t scratch_bytes) {
    return cluster_box_bytes(indices) <= scratch_bytes;
}
inline std::size_t cluster_mask_bytes(std::size_t indices, std::size_t rows, int reach) {
    return indices * rows * cluster_mask_bits(reach) / 8;
}

// The particles an exchange box (outbox, inbox) or the edge sort's arrays hold for n: a quarter
// more and 1024 (so one device has them too, at their least).
inline std::size_t box_capacity(std::size_t n) { return n + n / 4 + 1024; }

// The exchange flags for a window of n particles (cell_pipeline.cpp).
inline std::size_t flag_capacity(std::size_t n) { return n + n / 4 + 1; }

// Work-groups of the kick's reductions (physics.cpp): four per compute unit, 1 to 256.
inline std::size_t kick_groups(std::size_t compute_units) {
    return std::max<std::size_t>(1, std::min<std::size_t>(256, compute_units * 4));
}

// The local memory kernels may declare: the reported size less 1 KiB for the implementation's own
// (cl/quirks.cpp).
inline std::size_t usable_local_memory(std::size_t reported) { return reported > 2048 ? reported - 1024 : reported; }

// The largest power of two work-group at most `cap` (and the device's maximum, when known).
inline std::size_t work_group(std::size_t max_work_group_size, std::size_t cap = 256) {
    const std::size_t limit = std::min(cap, max_work_group_size ? max_work_group_size : cap);
    std::size_t p = 1;
    while (p * 2 <= limit) p *= 2;
    return p;
}

// Local memory of the radix sort's scatter (kernels/radix_sort.cl): the exchange tile (keys and
// values, one padding word per 32), the per-digit bases and the work-group scan's scratch.
inline std::size_t sort_scatter_local_bytes(std::size_t wg, std::size_t items, unsigned digit_bits) {
    const std::size_t tile = wg * items;
    const std::size_t padded = tile + tile / 32;
    return kUint * (2 * padded + (std::size_t{1} << digit_bits) + 2 * wg);
}

// Local memory of the scan's tiles (kernels/scan.cl): the work-group scan's scratch and, above 4
// items per work-item, the tile it transposes.
inline std::size_t scan_tiles_local_bytes(std::size_t wg, std::size_t items) {
    const std::size_t tile = wg * items;
    return kUint * (2 * wg + (items > 4 ? tile + tile / 32 : 0));
}

// Items per work-item where the caller gives none: 16, else 8, where local memory holds the tile;
// 4 otherwise.
inline std::size_t sort_items(std::size_t wg, std::size_t usable_local, unsigned digit_bits) {
    for (std::size_t items : {16, 8})
        if (sort_scatter_local_bytes(wg, items, digit_bits) <= usable_local) return items;
    return 4;
}
inline std::size_t scan_items(std::size_t wg, std::size_t usable_local) {
    for (std::size_t items : {16, 8})
        if (scan_tiles_local_bytes(wg, items) <= usable_local) return items;
    return 4;
}

// The radix sort's digit-count table for n pairs in tiles of `tile`: one count per digit and tile,
// and the total.
inline std::size_t sort_count_entries(std::size_t n, std::size_t tile, unsigned digit_bits) {
    return (std::size_t{1} << digit_bits) * ((n + tile - 1) / tile) + 1;
}

// The scratch a sort of n pairs borrows for its ping-pong (RadixSort::sort_through()): keys, then
// values from a 256-byte boundary.
inline std::size_t borrowed_elements(std::size_t n) { return 2 * ((n + 63) / 64 * 64); }

// Whether the step ahead runs (docs/multi_device.md): not --synchronous, some steps ahead, one
// slab or the cell tables kept over steps (run.list_buffer: the steps ahead keep them, the builds
// are synchronous), a step clock on every device (which needs cl_khr_fp64) and Leap-frog (a
// Symplectic step has two exchanges).
inline bool step_ahead(bool synchronous, std::size_t steps_ahead, std::size_t slabs, bool fp64, bool symplectic,
                       bool kept_tables = false) {
    return !synchronous && steps_ahead > 0 && (slabs == 1 || kept_tables) && fp64 && !symplectic;
}

}  // namespace clsph::device::sizing
