// The cell pipeline and the neighbour loop against brute force, on every device.
#include "pipeline_support.hpp"
#include "device/cell_pipeline.hpp"
#include "clsph/error.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

using namespace clsph;
using namespace clsph::device;

using namespace pipeline_test;

TEST_SUITE("pipeline") {
TEST_CASE("grid keys, cells and precision on the host") {
    Grid g(Box{{0, 0, 0}, {3.0, 1.0, 2.0}}, 0.1);
    CHECK(g.axis(0) == 0);  // longest axis is split
    const auto k = g.key(5, 3, 7);
    CHECK(g.cell_of_key(k) == std::array<std::uint32_t, 3>{5, 3, 7});
    CHECK(g.key(5, 3, 7) + 1 == g.key(5, 3, 8));  // b is least significant
    std::array<float, 3> off{};
    CHECK(g.locate({-0.01, 0.5, 0.5}, off) == g.params().invalid_key);
    CHECK(g.locate({3.0, 1.0, 2.0}, off) != g.params().invalid_key);  // max face is inside
    const auto key = g.locate({1.2345678, 0.5, 0.25}, off);
    const auto back = g.position(key, off);
    CHECK(back[0] == doctest::Approx(1.2345678).epsilon(1e-9));
    // Too many cells for 32-bit keys is a clear error.
    CHECK_THROWS_AS(Grid(Box{{0, 0, 0}, {1000, 1000, 1000}}, 0.001), SceneError);
    // Periodic: on a non-split axis only, at least 3 cells.
    CHECK_THROWS_AS(Grid(Box{{0, 0, 0}, {3, 1, 1}}, 0.1, -1, {true, false, false}), SceneError);
    CHECK_THROWS_AS(Grid(Box{{0, 0, 0}, {3, 0.2, 1}}, 0.1, -1, {false, true, false}), SceneError);
    Grid p(Box{{0, 0, 0}, {3, 1, 2}}, 0.3, -1, {false, true, false});
    CHECK(p.axis(1) == 1);  // the periodic axis takes the middle key position
    CHECK(static_cast<double>(p.params().cell_a) * p.params().n_a == doctest::Approx(1.0));
}

TEST_CASE("neighbours of random particles with empty cells match brute force") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(101);
        const Box box{{-1.0, 0.0, 0.5}, {1.0, 0.6, 1.3}};
        auto x = random_points(gen, 1500, Box{{-1.0, 0.0, 0.5}, {0.2, 0.6, 1.3}});  // x > 0.2 stays empty
        auto clump = random_points(gen, 300, Box{{0.6, 0.1, 0.6}, {0.7, 0.2, 0.7}});
        x.insert(x.end(), clump.begin(), clump.end());
        // A few particles outside the domain: removed and counted.
        x.push_back({-1.5, 0.3, 0.8});
        x.push_back({0.0, 0.3, 1.5});
        x.push_back({0.0, -0.01, 0.8});
        check_neighbours(*d, box, 0.1, {false, false, false}, x, 3, 102);
    }
}

TEST_CASE("particles on cell faces and domain faces") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        const double R = 0.25;
        const Box box{{0, 0, 0}, {1.0, 0.5, 0.75}};
        std::vector<std::array<double, 3>> x;
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 4; ++j)
                for (int k = 0; k <= 6; ++k) x.push_back({i * 0.125, j * 0.125, k * 0.125});  // on faces
        check_neighbours(*d, box, R, {false, false, false}, x, 0, 103);
    }
}

TEST_CASE("everything in one cell, a single particle, and nothing") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(104);
        const Box box{{0, 0, 0}, {2, 2, 2}};
        check_neighbours(*d, box, 0.5, {false, false, false},
                         random_points(gen, 200, Box{{1.01, 1.01, 1.01}, {1.02, 1.02, 1.02}}), 0, 105);
        check_neighbours(*d, box, 0.5, {false, false, false}, {{0.3, 0.4, 0.5}}, 0, 106);
        check_neighbours(*d, box, 0.5, {false, false, false}, {{0.3, 0.4, 0.5}, {3.0, 0.4, 0.5}}, 1, 107);
    }
}

TEST_CASE("periodic wrap on y") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(108);
        const Box box{{0, 0, 0}, {1.6, 0.5, 0.8}};
        auto x = random_points(gen, 1200, box);
        x.push_back({0.4, 0.0, 0.4});  // exactly on the wrap
        x.push_back({0.4, 0.4999, 0.4});
        check_neighbours(*d, box, 0.12, {false, true, false}, x, 0, 109);
    }
}

TEST_CASE("memory follows particles, not the domain") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(110);
        const auto x = random_points(gen, 20000, Box{{0, 0, 0}, {1, 0.5, 0.5}});
        std::size_t peak[2];
        for (int big = 0; big < 2; ++big) {
            const double scale = big ? 10.0 : 1.0;
            Grid grid(Box{{0, 0, 0}, {1 * scale, 0.5 * scale, 0.5 * scale}}, 0.02);
            d->memory().reset_peak();
            const auto base = d->memory().counters().current;
            {
                ParticleStore ps(*d, grid, x.size());
                ps.upload(make_particles(x));
                CellPipeline cp(*d, grid);
                cp.run(ps);
                d->finish();
            }
            peak[big] = d->memory().counters().peak - base;
        }
        MESSAGE("device bytes: domain x1 " << peak[0] << ", domain x10 per axis " << peak[1]);
        CHECK(std::abs(static_cast<double>(peak[1]) - static_cast<double>(peak[0])) < 0.05 * static_cast<double>(peak[0]));
    }
}

TEST_CASE("a slow particle far from the origin advances as it should") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        // 10 m from the origin at 1 mm/s, dt = 1e-5 s: 1e-8 m per step, 1e-5 m over 1000 steps. An
        // absolute float coordinate there has a spacing of ~1e-6 m and would not move at all.
        Grid grid(Box{{0, 0, 0}, {12, 1, 1}}, 0.012);
        ParticleStore ps(*d, grid, 4);
        Particles p = make_particles({{10.0, 0.5, 0.5}, {10.0061, 0.5, 0.5}});
        p.velocity = {{1e-3f, 0, 0}, {1e-3f, 0, 0}};
        ps.upload(p);
        CellPipeline cp(*d, grid);
        auto drift = d->kernel("selftest.cl", "drift");
        cp.run(ps);
        for (int step = 0; step < 1000; ++step) {
            drift.setArg(0, static_cast<cl_uint>(ps.ranges.active()));
            drift.setArg(1, 1e-5f);
            drift.setArg(2, ps.pos.get());
            drift.setArg(3, ps.velrho.get());
            d->launch("test.drift", drift, ps.ranges.active(), 64);
            cp.run(ps);
        }
        const Particles out = ps.download();
        REQUIRE(out.size() == 2);
        for (std::size_t i = 0; i < 2; ++i) {
            const double start = out.id[i] == p.id[0] ? 10.0 : 10.0061;
            const double moved = out.position[i][0] - start;
            CAPTURE(moved);
            CHECK(moved == doctest::Approx(1e-5).epsilon(0.03));  // float offsets: ~1e-10 m per step
        }
    }
}

TEST_CASE("morton order within cells: each cell by sub-cell code, then by its previous order, on every device") {
    // CellOrder::morton (order_within_cells in kernels/cells.cl) against the host: after the stable
    // sort by cell, each cell's particles by the Morton code of their sub-cell (2 levels: 64
    // sub-cells), ties in their order before (here, the upload's). The host computes the codes
    // from the offsets the device settled (pos.xyz) with the kernel's float arithmetic, so only the
    // order is tested. An order slot the kernel left unwritten would keep an index of the sort's
    // and move one particle twice: every id must come out exactly once. A dense clump puts
    // hundreds of particles in a few cells. Both reaches; arrival order too (the sort's, by upload
    // order within a cell).
    const Box box{{0.0, 0.0, 0.0}, {1.2, 0.6, 0.9}};
    const double R = 0.1;
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(141);
        auto x = random_points(gen, 3000, box);
        const auto clump = random_points(gen, 400, Box{{0.51, 0.21, 0.31}, {0.58, 0.28, 0.38}});
        x.insert(x.end(), clump.begin(), clump.end());
        for (const int reach : {1, 2})
            for (const CellOrder order : {CellOrder::morton, CellOrder::arrival}) {
                CAPTURE(reach);
                CAPTURE(std::string(cell_order_name(order)));
                Grid grid(box, R, -1, {false, false, false}, reach);
                const GridParams g = grid.params();
                ParticleStore ps(*d, grid, x.size());
                const Particles in = make_particles(x);
                ps.upload(in);
                CellPipeline cp(*d, grid);
                cp.set_order(order);
                const auto res = cp.run(ps);
                REQUIRE(res.active == x.size());
                std::vector<float> pos(4 * res.active);
                std::vector<std::uint32_t> id(res.active), keys(res.active);
                d->read(ps.pos, pos.data(), pos.size());
                d->read(ps.id, id.data(), id.size());
                d->read(ps.keys, keys.data(), keys.size());
                CHECK(std::set<std::uint32_t>(id.begin(), id.end()).size() == id.size());
                CHECK(std::is_sorted(keys.begin(), keys.end()));
                const auto scale = CellPipeline::sub_cell_scales(g);
                auto code_of = [&](std::size_t i) {
                    std::uint32_t q[3];
                    for (int k = 0; k < 3; ++k) {
                        const float off = pos[4 * i + static_cast<std::size_t>(grid.axis(k))];
                        const float u = std::floor(off * scale[static_cast<std::size_t>(k)]);
                        q[k] = static_cast<std::uint32_t>(std::clamp(static_cast<int>(u) + 2, 0, 3));
                    }
                    std::uint32_t c = 0;
                    for (int level = 1; level >= 0; --level)
                        c = (c << 3) | (((q[0] >> level) & 1u) << 2) | (((q[1] >> level) & 1u) << 1) | ((q[2] >> level) & 1u);
                    return c;
                };
                std::vector<std::size_t> expect(res.active);
                for (std::size_t i = 0; i < expect.size(); ++i) expect[i] = i;
                auto before = [&](std::size_t i) { return ((id[i] & CLSPH_ID_MASK) - 7) / 3; };  // upload position
                std::stable_sort(expect.begin(), expect.end(), [&](std::size_t a, std::size_t b) {
                    if (keys[a] != keys[b]) return keys[a] < keys[b];
                    if (order == CellOrder::morton && code_of(a) != code_of(b)) return code_of(a) < code_of(b);
                    return before(a) < before(b);
                });
                std::size_t out_of_place = 0, multi_code_cells = 0;
                for (std::size_t i = 0; i < expect.size(); ++i) out_of_place += expect[i] != i;
                for (std::size_t i = 1; i < expect.size(); ++i)
                    multi_code_cells += keys[i] == keys[i - 1] && code_of(i) != code_of(i - 1);
                CHECK(out_of_place == 0);
                CHECK(multi_code_cells > 0);  // the cells do hold several sub-cells: the test can fail
            }
    }
}
}
