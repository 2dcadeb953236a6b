// The radix sort against std::stable_sort on every device, fresh random keys (seed printed), poisoned
// outputs: every size, every key width, stability, other digit widths, borrowed buffers, bad arguments
// (the sizes and the checks: primitives_support.hpp; scan and compaction: test_primitives.cpp).
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
}
