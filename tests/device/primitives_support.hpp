// What the primitives' tests (test_primitives.cpp: scan and compaction; test_radix_sort.cpp) share:
// sizes, poisoned buffers, their CPU references and checks.
#pragma once
#include "clsph/error.hpp"
#include "device/primitives.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace primitives_test {

using namespace clsph;
using u32 = std::uint32_t;

inline constexpr u32 poison = 0xDEADBEEFu;
inline constexpr std::size_t guard = 16;  // poisoned elements after the end of every output

inline const std::vector<std::size_t> sizes = {0, 1, 2, 255, 256, 257, 100000, 1000003};

// "" when equal, else the first few differences (index: got vs expected).
inline std::string first_differences(const std::vector<u32>& got, const std::vector<u32>& want, const char* what) {
    std::ostringstream o;
    if (got.size() != want.size()) o << what << ": size " << got.size() << " vs expected " << want.size() << "\n";
    std::size_t shown = 0, total = 0;
    for (std::size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
        if (got[i] == want[i]) continue;
        if (shown < 8) {
            o << what << "[" << i << "] = 0x" << std::hex << got[i] << ", expected 0x" << want[i] << std::dec << "\n";
            ++shown;
        }
        ++total;
    }
    if (total) o << what << ": " << total << " of " << want.size() << " elements differ\n";
    return o.str();
}

inline std::vector<u32> random_words(std::mt19937_64& rng, std::size_t n) {
    std::vector<u32> v(n);
    for (auto& x : v) x = static_cast<u32>(rng());
    return v;
}

// A device buffer of n elements followed by `guard` poisoned ones, holding `data` at the start
// and poison everywhere else.
inline cl_rt::Buffer upload(cl_rt::Device& dev, const std::vector<u32>& data, std::size_t n, const char* what) {
    auto b = dev.alloc((n + guard) * sizeof(u32), what);
    dev.fill(b, poison, n + guard);
    dev.write(b, data.data(), std::min(n, data.size()));
    return b;
}

inline std::vector<u32> download(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t n) {
    std::vector<u32> v(n);
    dev.read(b, v.data(), n);
    return v;
}

// Elements [from, from + count) of `b` (as far as it holds) must still hold poison.
inline void check_poisoned(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t from, std::size_t count, const char* what) {
    const std::size_t end = std::min(b.bytes() / sizeof(u32), from + count);
    if (end <= from) return;
    std::vector<u32> v(end - from);
    dev.read(b, v.data(), v.size(), from);
    const auto bad = std::find_if(v.begin(), v.end(), [](u32 x) { return x != poison; });
    INFO(what << "[" << from + static_cast<std::size_t>(bad - v.begin()) << "] should not have been written");
    REQUIRE(bad == v.end());
}

// The guard elements after `used` must still hold poison.
inline void check_guard(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t used, const char* what) {
    check_poisoned(dev, b, used, guard, what);
}

inline std::vector<u32> cpu_exclusive_scan(const std::vector<u32>& in) {
    std::vector<u32> out(in.size() + 1);
    std::exclusive_scan(in.begin(), in.end(), out.begin(), u32{0});
    out[in.size()] = (in.empty() ? 0 : out[in.size() - 1] + in.back());
    return out;
}

inline void check_scan(cl_rt::Device& dev, device::Scan& scan, const std::vector<u32>& in, bool in_place) {
    const std::size_t n = in.size();
    CAPTURE(n);
    CAPTURE(in_place);
    const auto want = cpu_exclusive_scan(in);
    auto src = upload(dev, in, in_place ? n + 1 : n, "scan in");
    if (in_place) {
        scan.exclusive(src, src, n);
        REQUIRE_MESSAGE(first_differences(download(dev, src, n + 1), want, "out") == "", "");
        check_guard(dev, src, n + 1, "out");
        return;
    }
    auto out = upload(dev, {}, n + 1, "scan out");
    const u32 total = scan.exclusive_total(src, out, n);
    CHECK(total == want[n]);
    const std::string diff = first_differences(download(dev, out, n + 1), want, "out");
    REQUIRE_MESSAGE(diff.empty(), diff);
    check_guard(dev, out, n + 1, "out");
    REQUIRE(first_differences(download(dev, src, n), in, "in (must be unchanged)").empty());
}

// Expected result of a stable sort on the low key_bits bits: pairs (key, index) by masked key.
inline void cpu_sort(const std::vector<u32>& keys, unsigned key_bits, std::vector<u32>& sorted_keys,
              std::vector<u32>& sorted_values) {
    const u32 mask = key_bits == 32 ? 0xffffffffu : (1u << key_bits) - 1u;
    std::vector<u32> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](u32 a, u32 b) { return (keys[a] & mask) < (keys[b] & mask); });
    sorted_keys.resize(keys.size());
    sorted_values = order;
    for (std::size_t i = 0; i < keys.size(); ++i) sorted_keys[i] = keys[order[i]];
}

// The device's sorted pairs (keys, original index) against std::stable_sort's, and their guards.
inline void check_sorted(cl_rt::Device& dev, const cl_rt::Buffer& dk, const cl_rt::Buffer& dv, const std::vector<u32>& keys,
                  unsigned key_bits) {
    const std::size_t n = keys.size();
    std::vector<u32> want_keys, want_values;
    cpu_sort(keys, key_bits, want_keys, want_values);
    const std::string diff = first_differences(download(dev, dk, n), want_keys, "keys") +
                             first_differences(download(dev, dv, n), want_values, "values");
    REQUIRE_MESSAGE(diff.empty(), diff);
    check_guard(dev, dk, n, "keys");
    check_guard(dev, dv, n, "values");
}

// Sorts (keys, index) on the device and compares keys and values with std::stable_sort: since the
// values are the original indices, a stable sort is the only one that matches exactly.
inline void check_sort(cl_rt::Device& dev, device::RadixSort& sorter, const std::vector<u32>& keys, unsigned key_bits) {
    const std::size_t n = keys.size();
    CAPTURE(n);
    CAPTURE(key_bits);
    {
        // Sort poison first (one pass) so both the sorter's ping-pong buffers and ours hold poison:
        // any element the real sort fails to write then shows.
        auto pk = upload(dev, {}, n, "poison keys");
        auto pv = upload(dev, {}, n, "poison values");
        sorter.sort(pk, pv, n, 1);
    }
    std::vector<u32> values(n);
    std::iota(values.begin(), values.end(), 0u);
    auto dk = upload(dev, keys, n, "keys");
    auto dv = upload(dev, values, n, "values");
    const std::size_t key_capacity = dk.bytes(), value_capacity = dv.bytes();
    sorter.sort(dk, dv, n, key_bits);
    CHECK(dk.bytes() >= key_capacity);
    CHECK(dv.bytes() >= value_capacity);
    check_sorted(dev, dk, dv, keys, key_bits);
}

// As check_sort, through a borrowed scratch buffer (poisoned, with a guard after what it lends):
// the caller's buffers must keep their identity (no swap) and hold the result whether the number
// of passes is odd (copied back) or even, and nothing past the lent part may be written.
inline void check_sort_through(cl_rt::Device& dev, device::RadixSort& sorter, const std::vector<u32>& keys,
                        unsigned key_bits) {
    const std::size_t n = keys.size();
    CAPTURE(n);
    CAPTURE(key_bits);
    std::vector<u32> values(n);
    std::iota(values.begin(), values.end(), 0u);
    auto dk = upload(dev, keys, n, "keys");
    auto dv = upload(dev, values, n, "values");
    const std::size_t lent = device::RadixSort::borrowed_elements(n);
    auto scratch = upload(dev, {}, lent, "borrowed scratch");
    const cl_mem k0 = dk.get()(), v0 = dv.get()();
    sorter.sort_through(dk, dv, n, key_bits, scratch);
    CHECK(dk.get()() == k0);
    CHECK(dv.get()() == v0);
    check_sorted(dev, dk, dv, keys, key_bits);
    check_guard(dev, scratch, lent, "borrowed scratch");
}

inline void check_compact(cl_rt::Device& dev, device::Compact& compact, const std::vector<u32>& flags,
                   const std::vector<u32>& values) {
    const std::size_t n = flags.size();
    CAPTURE(n);
    std::vector<u32> want;
    for (std::size_t i = 0; i < n; ++i)
        if (flags[i] != 0) want.push_back(values[i]);
    auto df = upload(dev, flags, n, "flags");
    auto dv = upload(dev, values, n, "values");
    auto out = upload(dev, {}, n, "compacted");
    const std::size_t count = compact.compact(df, dv, out, n);
    REQUIRE(count == want.size());
    const std::string diff = first_differences(download(dev, out, count), want, "out");
    REQUIRE_MESSAGE(diff.empty(), diff);
    check_poisoned(dev, out, count, n + guard - count, "out (past the kept elements)");
}

}  // namespace primitives_test
