// Data-parallel primitives on one device, in portable OpenCL C 1.2 (local memory and barriers, no
// subgroups, no inter-work-group forward progress): radix sort of (key, value) pairs, exclusive
// scan, stream compaction. Each object owns its scratch buffers (tracked by the device's memory
// accounting, grown on demand, never shrunk) and its kernels (built once per device and options).
#pragma once
#include "cl/device.hpp"
#include "device/sizing.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace clsph::device {

// Exclusive prefix sum of uint32 (wrapping on overflow, like std::exclusive_scan on uint32_t).
class Scan {
public:
    // Launch shape; zeros pick per-device defaults. Benchmarks sweep these; the engine keeps the
    // defaults.
    struct Config {
        std::size_t work_group = 0;  // work-items per group, a power of two (0: the device's, <= 256)
        std::size_t items = 0;       // elements per work-item, a multiple of 4 (0: 16, less if local memory is short)
        std::string name = "scan";   // launches are named "<name>.reduce" and "<name>.tiles"
        // Where the tile sums are few (at most 4 per work-item), each work-group of the tiles adds
        // up those before its own instead of a scan of them: two launches for any n up to
        // 4 * WG tiles. Off: the launches before they were fused (Seams::unfused), the same sums.
        bool fold_offsets = true;
    };
    explicit Scan(cl_rt::Device& device);
    Scan(cl_rt::Device& device, const Config& config);
    // out[i] = in[0] + ... + in[i-1] for i in [0, n], so out[n] is the total: `out` must hold n + 1
    // elements. `in` and `out` may be the same buffer only if it holds n + 1 elements.
    // Asynchronous: enqueued on the device's queue.
    void exclusive(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n);
    // As exclusive(), then reads back and returns the total (a blocking read of one uint).
    std::uint32_t exclusive_total(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n);
    // As exclusive(), counting each input element as 1 if it is non-zero and 0 otherwise (the scan
    // of stream compaction, without a pass to turn flags into 0/1).
    void exclusive_flags(const cl_rt::Buffer& flags, cl_rt::Buffer& out, std::size_t n);
    // As exclusive(), counting element i as 1 where it starts a run of equal values (i == 0 or
    // keys[i] != keys[i - 1]) and 0 otherwise: in sorted keys, out[i] is the number of distinct
    // keys before i and out[n] their count. `keys` and `out` must be different buffers.
    void exclusive_starts(const cl_rt::Buffer& keys, cl_rt::Buffer& out, std::size_t n);
    std::size_t scratch_bytes() const;
    std::size_t tile() const;  // elements per work-group, as resolved for this device

private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

// Stable LSD radix sort of (uint32 key, uint32 value) pairs on the low `key_bits` bits of the key
// (1..32; higher bits are ignored for ordering but kept). The sorted pairs end up in `keys` and
// `values`: the sort ping-pongs between them and its own scratch buffers and may swap the Buffer
// objects (so kernel arguments bound to them must be set again after a sort). A swapped-in Buffer
// is never smaller than the one it replaces. One pass per digit: ceil(key_bits / digit_bits).
class RadixSort {
public:
    struct Config {
        std::size_t work_group = 0;  // work-items per group, a power of two >= 16 (0: the device's, <= 256)
        std::size_t items = 0;       // pairs per work-item, a multiple of 4 (0: the most local memory allows, <= 16)
        unsigned digit_bits = sizing::kDigitBits;  // bits sorted per pass, 1..8
        std::string name = "sort";   // launches: "<name>.histogram", "<name>.scan.*", "<name>.scatter"
        // Where the tiles are few (128 at most), the scatter adds up the digit counts itself: two
        // launches a pass instead of three or more. Off: the launches before they were fused
        // (Seams::unfused; its scan's tiles unfolded too), the same order.
        bool fold_scan = true;
    };
    explicit RadixSort(cl_rt::Device& device);
    RadixSort(cl_rt::Device& device, const Config& config);
    void sort(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits);
    // As sort(), but ping-pongs through `scratch` (keys from element 0, values from element
    // borrowed_elements(n) / 2) instead of buffers of its own, so it needs no memory beyond the digit
    // counts; `scratch` must hold borrowed_elements(n) uint and its contents are lost. The buffers are
    // never swapped: after an odd number of passes the pairs are copied back into keys and values.
    void sort_through(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits,
                      const cl_rt::Buffer& scratch);
    // The first pass's histogram made by the caller's own kernel (a launch fewer: the step ahead's
    // keys, kernels/drift_histogram.cl): built with tile_options(), in work-groups of
    // config().work_group over tiles of tile() pairs, it writes for tile g and each digit d of the
    // keys' lowest first_bits(key_bits) bits their count to first_counts(n)[d * groups + g];
    // sort_through_counted() then sorts as sort_through() does, without that histogram.
    std::string tile_options() const;
    unsigned first_bits(unsigned key_bits) const;
    const cl_rt::Buffer& first_counts(std::size_t n);
    void sort_through_counted(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits,
                              const cl_rt::Buffer& scratch);
    static std::size_t borrowed_elements(std::size_t n);  // uint a sort_through() of n pairs borrows
    std::size_t scratch_bytes() const;
    std::size_t tile() const;                      // pairs per work-group, as resolved for this device
    unsigned passes(unsigned key_bits) const;      // passes a sort of key_bits bits makes
    const Config& config() const;                  // as resolved for this device

private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

// Stream compaction: keeps the elements whose flag is non-zero, in order, and returns how many.
class Compact {
public:
    explicit Compact(cl_rt::Device& device);
    // flags and values may be the same buffer (keep the non-zero elements).
    // out[j] = values[i] for the j-th i with flags[i] != 0; `out` must hold n elements.
    std::size_t compact(const cl_rt::Buffer& flags, const cl_rt::Buffer& values, cl_rt::Buffer& out, std::size_t n);

private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

}  // namespace clsph::device
