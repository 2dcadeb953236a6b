// Scan, radix sort and compaction against plain C++ on every device, on random inputs drawn fresh
// each run (the seed is printed). Outputs are poisoned first so that unwritten elements show, and a
// failure prints the first elements that differ.
//
// Sizes: 0, 1, 2, 255, 256, 257, 100 000 and a large odd size, 1 000 003 (hundreds of tiles with a
// partial last one, and a recursive scan of the tile sums); key widths 1..32 at a few tiles, three
// widths at the large size. The same sizes on every device (rusticl included): the suite stays
// within about a minute on a 2-core CI machine with three CPU devices and a cold pocl cache.
#include "primitives_support.hpp"
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

using namespace primitives_test;

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
