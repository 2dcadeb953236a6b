// Scan, radix sort and compaction against plain C++ on every device, on random inputs drawn fresh
// each run (the seed is printed). Outputs are poisoned first so that unwritten elements show, and a
// failure prints the first elements that differ.
//
// Sizes: 0, 1, 2, 255, 256, 257, 100 000 and a large odd size, 1 000 003 (hundreds of tiles with a
// partial last one, and a recursive scan of the tile sums); key widths 1..32 at a few tiles, three
// widths at the large size. The same sizes on every device (rusticl included): the suite stays
// within about a minute on a 2-core CI machine with three CPU devices and a cold pocl cache.
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

using namespace clsph;
using u32 = std::uint32_t;

namespace {

constexpr u32 poison = 0xDEADBEEFu;
constexpr std::size_t guard = 16;  // poisoned elements after the end of every output

const std::vector<std::size_t> sizes = {0, 1, 2, 255, 256, 257, 100000, 1000003};

// "" when equal, else the first few differences (index: got vs expected).
std::string first_differences(const std::vector<u32>& got, const std::vector<u32>& want, const char* what) {
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

std::vector<u32> random_words(std::mt19937_64& rng, std::size_t n) {
    std::vector<u32> v(n);
    for (auto& x : v) x = static_cast<u32>(rng());
    return v;
}

// A device buffer of n elements followed by `guard` poisoned ones, holding `data` at the start
// and poison everywhere else.
cl_rt::Buffer upload(cl_rt::Device& dev, const std::vector<u32>& data, std::size_t n, const char* what) {
    auto b = dev.alloc((n + guard) * sizeof(u32), what);
    dev.fill(b, poison, n + guard);
    dev.write(b, data.data(), std::min(n, data.size()));
    return b;
}

std::vector<u32> download(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t n) {
    std::vector<u32> v(n);
    dev.read(b, v.data(), n);
    return v;
}

// Elements [from, from + count) of `b` (as far as it holds) must still hold poison.
void check_poisoned(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t from, std::size_t count, const char* what) {
    const std::size_t end = std::min(b.bytes() / sizeof(u32), from + count);
    if (end <= from) return;
    std::vector<u32> v(end - from);
    dev.read(b, v.data(), v.size(), from);
    const auto bad = std::find_if(v.begin(), v.end(), [](u32 x) { return x != poison; });
    INFO(what << "[" << from + static_cast<std::size_t>(bad - v.begin()) << "] should not have been written");
    REQUIRE(bad == v.end());
}

// The guard elements after `used` must still hold poison.
void check_guard(cl_rt::Device& dev, const cl_rt::Buffer& b, std::size_t used, const char* what) {
    check_poisoned(dev, b, used, guard, what);
}

std::vector<u32> cpu_exclusive_scan(const std::vector<u32>& in) {
    std::vector<u32> out(in.size() + 1);
    std::exclusive_scan(in.begin(), in.end(), out.begin(), u32{0});
    out[in.size()] = (in.empty() ? 0 : out[in.size() - 1] + in.back());
    return out;
}

void check_scan(cl_rt::Device& dev, device::Scan& scan, const std::vector<u32>& in, bool in_place) {
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
void cpu_sort(const std::vector<u32>& keys, unsigned key_bits, std::vector<u32>& sorted_keys,
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
void check_sorted(cl_rt::Device& dev, const cl_rt::Buffer& dk, const cl_rt::Buffer& dv, const std::vector<u32>& keys,
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
void check_sort(cl_rt::Device& dev, device::RadixSort& sorter, const std::vector<u32>& keys, unsigned key_bits) {
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
void check_sort_through(cl_rt::Device& dev, device::RadixSort& sorter, const std::vector<u32>& keys,
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

void check_compact(cl_rt::Device& dev, device::Compact& compact, const std::vector<u32>& flags,
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

}  // namespace

TEST_SUITE("primitives") {
TEST_CASE("scan: exclusive scan with the total at out[n], every size") {
    auto rng = test::rng(1);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::Scan scan(*dev);
        for (std::size_t n : sizes) {
            // Full 32-bit values: the sum wraps, as std::exclusive_scan's on uint32_t does.
            check_scan(*dev, scan, random_words(rng, n), false);
            // Small values too, so that a wrong result cannot hide in wrap-around.
            std::vector<u32> small(n);
            for (auto& x : small) x = static_cast<u32>(rng() % 4);
            check_scan(*dev, scan, small, n % 2 == 1);
        }
        // Sizes around multiples of the tile.
        const std::size_t t = scan.tile();
        for (std::size_t n : {t - 1, t, t + 1, 2 * t}) check_scan(*dev, scan, random_words(rng, n), false);
    }
}

TEST_CASE("scan: deep recursion with small tiles") {
    auto rng = test::rng(9);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::Scan::Config config;
        config.work_group = 16;
        config.items = 4;
        device::Scan scan(*dev, config);
        REQUIRE(scan.tile() == 64);
        // 64^3 + 5 elements: four levels of tile sums (262149 -> 4097 -> 65 -> 2 -> 1).
        for (std::size_t n : {std::size_t{63}, std::size_t{64}, std::size_t{65}, std::size_t{4096}, std::size_t{4097},
                              std::size_t{64 * 64 * 64 + 5}})
            check_scan(*dev, scan, random_words(rng, n), n % 2 == 1);
    }
}

TEST_CASE("scan: flags count as 0 or 1") {
    auto rng = test::rng(2);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::Scan scan(*dev);
        for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{257}, std::size_t{100000}}) {
            CAPTURE(n);
            std::vector<u32> flags(n), as01(n);
            for (std::size_t i = 0; i < n; ++i) {
                flags[i] = rng() % 3 == 0 ? 0u : static_cast<u32>(rng());
                as01[i] = flags[i] != 0;
            }
            auto df = upload(*dev, flags, n, "flags");
            auto out = upload(*dev, {}, n + 1, "out");
            scan.exclusive_flags(df, out, n);
            const std::string diff = first_differences(download(*dev, out, n + 1), cpu_exclusive_scan(as01), "out");
            REQUIRE_MESSAGE(diff.empty(), diff);
        }
    }
}

TEST_CASE("scan: run starts count as 1 (the compaction of sorted cell keys), across tiles") {
    auto rng = test::rng(10);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::Scan scan(*dev);
        const std::size_t t = scan.tile();
        for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{257}, t - 1, t, t + 1,
                              3 * t + 5, std::size_t{100000}}) {
            CAPTURE(n);
            // Sorted keys in runs of 1 to 8, some runs crossing tile boundaries; the first key 0
            // (a start all the same).
            std::vector<u32> keys(n), starts(n);
            u32 key = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (i > 0 && rng() % 4 == 0) key += 1 + static_cast<u32>(rng() % 3);
                keys[i] = key;
            }
            if (n > t + 1) keys[t] = keys[t - 1];  // a run across the first tile boundary
            for (std::size_t i = 0; i < n; ++i) starts[i] = i == 0 || keys[i] != keys[i - 1];
            auto dk = upload(*dev, keys, n, "keys");
            auto out = upload(*dev, {}, n + 1, "out");
            scan.exclusive_starts(dk, out, n);
            const std::string diff = first_differences(download(*dev, out, n + 1), cpu_exclusive_scan(starts), "out");
            REQUIRE_MESSAGE(diff.empty(), diff);
            check_guard(*dev, out, n + 1, "out");
        }
        auto both = dev->alloc(101 * sizeof(u32), "keys and out");
        CHECK_THROWS_AS(scan.exclusive_starts(both, both, 100), Error);  // reads the element before: not in place
    }
}

TEST_CASE("scan and radix sort: tile sums added up where they are used equal the scanned ones") {
    // Config::fold_offsets / fold_scan off: the launches before fusion (Seams::unfused). Small
    // tiles (64 pairs or elements) so that a few thousand elements make many tiles, on both sides
    // of the bounds where folding stops (4 tile sums a work-item; 128 tiles of the sort).
    auto rng = test::rng(11);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        for (bool fold : {true, false}) {
            CAPTURE(fold);
            device::Scan::Config sc;
            sc.work_group = 16;
            sc.items = 4;
            sc.fold_offsets = fold;
            device::Scan scan(*dev, sc);
            for (std::size_t n : {std::size_t{65}, std::size_t{64 * 64}, std::size_t{64 * 64 + 1}, std::size_t{5000}})
                check_scan(*dev, scan, random_words(rng, n), n % 2 == 1);
            device::RadixSort::Config rc;
            rc.work_group = 16;
            rc.items = 4;
            rc.fold_scan = fold;
            device::RadixSort sorter(*dev, rc);
            REQUIRE(sorter.tile() == 64);
            for (std::size_t n : {std::size_t{130}, std::size_t{64 * 128}, std::size_t{64 * 128 + 1}})
                for (unsigned bits : {5u, 19u}) check_sort(*dev, sorter, random_words(rng, n), bits);
        }
    }
}

TEST_CASE("scan: too small buffers are refused") {
    auto* dev = test::devices().front();
    device::Scan scan(*dev);
    auto in = dev->alloc(100 * sizeof(u32), "in");
    auto out = dev->alloc(100 * sizeof(u32), "out");
    CHECK_THROWS_AS(scan.exclusive(in, out, 100), Error);  // out needs n + 1
    CHECK_THROWS_AS(scan.exclusive(in, out, 101), Error);
}

TEST_CASE("radix sort: every size, random 32-bit keys") {
    auto rng = test::rng(3);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::RadixSort sorter(*dev);
        for (std::size_t n : sizes) {
            // Keys have bits above key_bits set: they must not affect the order but must survive.
            check_sort(*dev, sorter, random_words(rng, n), 32);
            check_sort(*dev, sorter, random_words(rng, n), 19);
        }
    }
}

TEST_CASE("radix sort: every key width 1..32") {
    auto rng = test::rng(4);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::RadixSort sorter(*dev);
        // Several tiles, a partial last tile, and (for narrow keys) long runs of equal keys.
        const std::size_t n = 3 * sorter.tile() + 123;
        for (unsigned bits = 1; bits <= 32; ++bits) check_sort(*dev, sorter, random_words(rng, n), bits);
    }
}

TEST_CASE("radix sort: large sizes at the widths the engine uses") {
    auto rng = test::rng(5);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::RadixSort sorter(*dev);
        const std::size_t n = sizes.back();
        for (unsigned bits : {8u, 17u, 24u}) check_sort(*dev, sorter, random_words(rng, n), bits);
    }
}

TEST_CASE("radix sort: stable on structured keys") {
    auto rng = test::rng(6);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::RadixSort sorter(*dev);
        const std::size_t n = 100000;
        // All keys equal (one digit everywhere), and only high garbage bits differing.
        std::vector<u32> same(n, 0x1234u);
        check_sort(*dev, sorter, same, 16);
        std::vector<u32> garbage(n);
        for (auto& k : garbage) k = static_cast<u32>(rng()) << 12 | 0x0abu;
        check_sort(*dev, sorter, garbage, 12);
        // Nearly sorted (cell keys one step after the last sort), ascending and descending.
        std::vector<u32> near(n), down(n);
        for (std::size_t i = 0; i < n; ++i) {
            near[i] = static_cast<u32>(i / 7 + rng() % 3);
            down[i] = static_cast<u32>((n - i) / 5);
        }
        check_sort(*dev, sorter, near, 20);
        check_sort(*dev, sorter, down, 20);
        // Few distinct keys spread over a wide range: many equal keys in every digit pass.
        std::vector<u32> few(n);
        const u32 palette[5] = {0u, 0xffffffu, 0x80000000u, 0x00ff00ffu, 0xffffffffu};
        for (auto& k : few) k = palette[rng() % 5];
        check_sort(*dev, sorter, few, 32);
    }
}

TEST_CASE("radix sort: another digit width and tile sort the same") {
    auto rng = test::rng(7);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        // 5-bit digits: local splits of 4 + 1 bits, and a narrower last pass (13 = 5 + 5 + 3).
        // Small tiles of 256 pairs. (Each configuration is a kernel build: pocl takes seconds.)
        device::RadixSort::Config config;
        config.digit_bits = 5;
        config.items = 4;
        config.work_group = 64;
        device::RadixSort sorter(*dev, config);
        CHECK(sorter.tile() == 256);
        CHECK(sorter.passes(13) == 3);
        CHECK(sorter.passes(32) == 7);
        for (unsigned bits : {1u, 13u, 32u}) check_sort(*dev, sorter, random_words(rng, 5000), bits);
    }
}

TEST_CASE("radix sort: through a borrowed buffer, odd and even pass counts") {
    auto rng = test::rng(9);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::RadixSort sorter(*dev);
        // 8 bits: one pass (copied back); 16: two; 19: three; 32: four.
        for (std::size_t n : sizes)
            for (unsigned bits : {8u, 16u, 19u, 32u}) check_sort_through(*dev, sorter, random_words(rng, n), bits);
    }
}

TEST_CASE("radix sort: bad arguments are refused") {
    auto* dev = test::devices().front();
    device::RadixSort sorter(*dev);
    auto k = dev->alloc(10 * sizeof(u32), "k");
    auto v = dev->alloc(10 * sizeof(u32), "v");
    CHECK_THROWS_AS(sorter.sort(k, v, 10, 0), Error);
    CHECK_THROWS_AS(sorter.sort(k, v, 10, 33), Error);
    CHECK_THROWS_AS(sorter.sort(k, v, 11, 8), Error);
    auto small = dev->alloc((device::RadixSort::borrowed_elements(10) - 1) * sizeof(u32), "small scratch");
    CHECK_THROWS_AS(sorter.sort_through(k, v, 10, 8, small), Error);
    device::RadixSort::Config bad;
    bad.digit_bits = 9;
    CHECK_THROWS_AS(device::RadixSort(*dev, bad), Error);
}

TEST_CASE("compact: keeps flagged elements in order and returns the count") {
    auto rng = test::rng(8);
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::Compact compact(*dev);
        for (std::size_t n : sizes) {
            const auto values = random_words(rng, n);
            // Densities from none to all; non-zero flags are arbitrary words, not just 1.
            for (unsigned keep_in_4 : {0u, 1u, 3u, 4u}) {
                CAPTURE(keep_in_4);
                std::vector<u32> flags(n);
                for (auto& f : flags) f = rng() % 4 < keep_in_4 ? static_cast<u32>(rng() | 1u) : 0u;
                check_compact(*dev, compact, flags, values);
            }
        }
    }
}
}
