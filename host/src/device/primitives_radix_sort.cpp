// RadixSort: LSD passes of up to digit_bits bits, each histogram -> scan -> scatter over tiles of
// WG * ITEMS pairs (see kernels/radix_sort.cl), ping-ponging between the caller's buffers and ours
// or, in sort_through(), a buffer the caller lends.
#include "device/primitives.hpp"

#include "device/primitives_launch.hpp"
#include "device/sizing.hpp"

#include "clsph/error.hpp"

#include <algorithm>

namespace clsph::device {
namespace {

using sizing::sort_scatter_local_bytes;

// The most tiles whose digit counts the scatter adds up itself (RadixSort::Config::fold_scan).
constexpr std::size_t kFoldedGroups = 128;

}  // namespace

struct RadixSort::Impl {
    cl_rt::Device& dev;
    Config config;
    std::size_t tile = 0;
    cl::Kernel histogram, scatter;
    Scan scan;  // of the digit-count table
    cl_rt::Buffer keys_alt, values_alt, counts;

    Impl(cl_rt::Device& device, Config c)
        : dev(device), config(std::move(c)), scan(device, Scan::Config{0, 0, config.name + ".scan", config.fold_scan}) {
        if (config.digit_bits < 1 || config.digit_bits > 8)
            throw Error("radix sort: digit_bits must be 1..8, not " + std::to_string(config.digit_bits));
        const std::size_t wg0 = config.work_group ? config.work_group : dev.work_group_size(256);
        if (wg0 < 16) throw Error("radix sort: work-groups of " + std::to_string(wg0) + " are too small (16 or more)");
        if (config.items == 0) {
            // Larger tiles write longer runs per digit (better coalesced) and leave a smaller table
            // to scan; local memory bounds them (32 KiB on rusticl: 8 per work-item at 256).
            config.items = sizing::sort_items(wg0, dev.quirks().usable_local_memory, config.digit_bits);
        }
        if (config.items % 4 != 0)
            throw Error("radix sort: items per work-item must be a multiple of 4, not " + std::to_string(config.items));
        if (sort_scatter_local_bytes(wg0, config.items, config.digit_bits) > dev.quirks().usable_local_memory)
            throw Error("radix sort: tiles of " + std::to_string(wg0 * config.items) + " pairs need " +
                        std::to_string(sort_scatter_local_bytes(wg0, config.items, config.digit_bits)) +
                        " bytes of local memory, more than the " +
                        std::to_string(dev.quirks().usable_local_memory) + " usable on " + dev.label());
        if (wg0 * config.items >= 65536) throw Error("radix sort: tiles must hold fewer than 65536 pairs");
        config.work_group = resolve_work_group(dev, config.work_group, 256, [&](std::size_t wg) {
            const std::string options = "-DWG=" + std::to_string(wg) + " -DITEMS=" + std::to_string(config.items) +
                                        " -DDIGIT_BITS=" + std::to_string(config.digit_bits);
            histogram = dev.kernel("radix_sort.cl", "sort_histogram", options);
            scatter = dev.kernel("radix_sort.cl", "sort_scatter", options);
            return std::vector<cl::Kernel*>{&histogram, &scatter};
        });
        tile = config.work_group * config.items;
    }

    unsigned passes(unsigned key_bits) const { return (key_bits + config.digit_bits - 1) / config.digit_bits; }

    // Checks the arguments and sizes the digit counts; false when there is nothing to sort.
    bool prepare(const cl_rt::Buffer& keys, const cl_rt::Buffer& values, std::size_t n, unsigned key_bits) {
        if (key_bits < 1 || key_bits > 32)
            throw Error("radix sort: key_bits must be 1..32, not " + std::to_string(key_bits));
        require_elements("radix sort keys", keys, n);
        require_elements("radix sort values", values, n);
        if (n < 2) return false;
        as_uint(n);
        ensure_capacity(dev, counts, sizing::sort_count_entries(n, tile, config.digit_bits) * sizeof(cl_uint),
                        "radix sort digit counts");
        return true;
    }

    std::size_t groups_of(std::size_t n) const { return (n + tile - 1) / tile; }

    // A pass's array: a buffer and the element its array starts at.
    struct Span {
        const cl_rt::Buffer* buffer;
        cl_uint at;
    };

    // One pass on the digit at `shift`, from (keys, values) to (keys_out, values_out).
    // `counted`: the digit counts are in `counts` already (a caller's kernel: sort_through_counted).
    void pass(Span keys, Span values, Span keys_out, Span values_out, std::size_t n, unsigned shift, unsigned key_bits,
              bool counted = false) {
        const cl_uint count = as_uint(n);
        const std::size_t groups = groups_of(n);
        const std::size_t wg = config.work_group;
        const cl_uint bits = std::min(config.digit_bits, key_bits - shift);
        const std::size_t entries = (std::size_t{1} << bits) * groups;
        if (!counted) {
            set_args(histogram, keys.buffer->get(), keys.at, count, cl_uint{shift}, bits, as_uint(groups), counts.get());
            dev.launch(config.name + ".histogram", histogram, groups * wg, wg);
        }
        // Few tiles: the scatter's work-groups add up the digit counts before their own instead of
        // a scan of the table (each reads the whole table: groups^2 digits in all, hence the bound).
        const bool fold = config.fold_scan && groups <= kFoldedGroups;
        if (!fold) scan.exclusive(counts, counts, entries);
        set_args(scatter, keys.buffer->get(), keys.at, values.buffer->get(), values.at, keys_out.buffer->get(),
                 keys_out.at, values_out.buffer->get(), values_out.at, count, cl_uint{shift}, bits, as_uint(groups),
                 counts.get(), cl_uint{fold ? 1u : 0u});
        dev.launch(config.name + ".scatter", scatter, groups * wg, wg);
    }

    void sort(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits) {
        if (!prepare(keys, values, n, key_bits)) return;
        // Our buffers trade places with the caller's: size them so that the caller never gets a
        // smaller buffer than it gave us.
        ensure_capacity(dev, keys_alt, std::max(keys.bytes(), n * sizeof(cl_uint)), "radix sort keys (ping-pong)");
        ensure_capacity(dev, values_alt, std::max(values.bytes(), n * sizeof(cl_uint)), "radix sort values (ping-pong)");
        for (unsigned shift = 0; shift < key_bits; shift += config.digit_bits) {
            pass({&keys, 0}, {&values, 0}, {&keys_alt, 0}, {&values_alt, 0}, n, shift, key_bits);
            keys.swap(keys_alt);
            values.swap(values_alt);
        }
    }

    void sort_through(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits,
                      const cl_rt::Buffer& scratch, bool counted = false) {
        if (!prepare(keys, values, n, key_bits)) return;
        const std::size_t half = RadixSort::borrowed_elements(n) / 2;
        if (scratch.bytes() < 2 * half * sizeof(cl_uint))
            throw Error("radix sort: a borrowed buffer of " + std::to_string(scratch.bytes()) + " bytes is too small for " +
                        std::to_string(n) + " pairs (" + std::to_string(2 * half * sizeof(cl_uint)) + " needed)");
        as_uint(2 * half);
        const Span home[2] = {{&keys, 0}, {&values, 0}};
        const Span away[2] = {{&scratch, 0}, {&scratch, as_uint(half)}};
        bool at_home = true;
        for (unsigned shift = 0; shift < key_bits; shift += config.digit_bits) {
            const Span* in = at_home ? home : away;
            const Span* out = at_home ? away : home;
            pass(in[0], in[1], out[0], out[1], n, shift, key_bits, counted && shift == 0);
            at_home = !at_home;
        }
        // After an odd number of passes the pairs are in the scratch: copy them home.
        if (!at_home) {
            dev.copy(scratch, keys, n * sizeof(cl_uint), 0, 0);
            dev.copy(scratch, values, n * sizeof(cl_uint), half * sizeof(cl_uint), 0);
        }
    }
};

RadixSort::RadixSort(cl_rt::Device& device) : RadixSort(device, Config{}) {}
RadixSort::RadixSort(cl_rt::Device& device, const Config& config) : impl_(std::make_shared<Impl>(device, config)) {}

void RadixSort::sort(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits) {
    impl_->sort(keys, values, n, key_bits);
}

void RadixSort::sort_through(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits,
                             const cl_rt::Buffer& scratch) {
    impl_->sort_through(keys, values, n, key_bits, scratch);
}

void RadixSort::sort_through_counted(cl_rt::Buffer& keys, cl_rt::Buffer& values, std::size_t n, unsigned key_bits,
                                     const cl_rt::Buffer& scratch) {
    impl_->sort_through(keys, values, n, key_bits, scratch, true);
}

std::string RadixSort::tile_options() const {
    return "-DWG=" + std::to_string(impl_->config.work_group) + " -DITEMS=" + std::to_string(impl_->config.items) +
           " -DDIGIT_BITS=" + std::to_string(impl_->config.digit_bits);
}

unsigned RadixSort::first_bits(unsigned key_bits) const { return std::min(impl_->config.digit_bits, key_bits); }

const cl_rt::Buffer& RadixSort::first_counts(std::size_t n) {
    ensure_capacity(impl_->dev, impl_->counts,
                    sizing::sort_count_entries(n, impl_->tile, impl_->config.digit_bits) * sizeof(cl_uint),
                    "radix sort digit counts");
    return impl_->counts;
}

std::size_t RadixSort::borrowed_elements(std::size_t n) { return sizing::borrowed_elements(n); }

std::size_t RadixSort::scratch_bytes() const {
    return impl_->keys_alt.bytes() + impl_->values_alt.bytes() + impl_->counts.bytes() + impl_->scan.scratch_bytes();
}

std::size_t RadixSort::tile() const { return impl_->tile; }
unsigned RadixSort::passes(unsigned key_bits) const { return impl_->passes(key_bits); }
const RadixSort::Config& RadixSort::config() const { return impl_->config; }

}  // namespace clsph::device
