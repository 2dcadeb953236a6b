// The cell pipeline and the neighbour loop against brute force, on every device.
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

namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;

Particles make_particles(const std::vector<std::array<double, 3>>& x) {
    Particles p;
    for (std::size_t i = 0; i < x.size(); ++i)
        p.push_back(static_cast<std::uint32_t>(i * 3 + 7), i % 5 == 0 ? ParticleType::boundary : ParticleType::fluid,
                    x[i], {0.1f, -0.2f, 0.3f}, 1000.0f + static_cast<float>(i % 13), 0.0f);
    return p;
}

struct ProbeResult {
    std::vector<std::uint32_t> count;
    std::vector<float> sum;
    std::vector<std::vector<std::uint32_t>> lists;  // per sampled particle, sorted ids
};

// Runs the neighbour_probe interaction (fine or coarse) over the owned particles of `ps`.
// quantity[j] = f(id_j); samples are positions in the (sorted) store.
ProbeResult probe(cl_rt::Device& d, ParticleStore& ps, CellPipeline& cp, const Grid& grid, double support, bool coarse,
                  const std::vector<float>& quantity_sorted, const std::vector<std::size_t>& samples) {
    const std::size_t n = ps.ranges.active();
    const cl_uint max_list = 1024;
    const std::size_t wg = 64;
    std::string opts = grid.kernel_options();
    if (coarse) opts += " -DCLSPH_COARSE -DWG=" + std::to_string(wg);
    auto k = d.kernel("neighbour_probe.cl", "neighbour_probe", opts);
    auto q = d.alloc(std::max<std::size_t>(n, 1) * sizeof(float), "q");
    auto slot = d.alloc(std::max<std::size_t>(n, 1) * sizeof(cl_int), "slot");
    auto list = d.alloc(std::max<std::size_t>(samples.size(), 1) * max_list * sizeof(cl_uint), "list");
    auto cnt = d.alloc(std::max<std::size_t>(n, 1) * sizeof(cl_uint), "count");
    auto sum = d.alloc(std::max<std::size_t>(n, 1) * sizeof(float), "sum");
    std::vector<cl_int> slots(n, -1);
    for (std::size_t s = 0; s < samples.size(); ++s) slots[samples[s]] = static_cast<cl_int>(s);
    d.write(q, quantity_sorted.data(), n);
    d.write(slot, slots.data(), n);
    d.fill(cnt, kPoison, std::max<std::size_t>(n, 1));
    d.fill(sum, kPoison, std::max<std::size_t>(n, 1));
    d.fill(list, kPoison, std::max<std::size_t>(samples.size(), 1) * max_list);
    const GridParams g = grid.params();
    cl_uint a = 0;
    k.setArg(a++, static_cast<cl_uint>(ps.ranges.first_owned()));
    k.setArg(a++, static_cast<cl_uint>(ps.ranges.end_owned()));
    k.setArg(a++, g);
    k.setArg(a++, static_cast<float>(support * support));
    k.setArg(a++, ps.pos.get());
    k.setArg(a++, coarse ? cp.cell_start().get() : ps.vals.get());
    k.setArg(a++, cp.ranges().get());
    k.setArg(a++, q.get());
    k.setArg(a++, ps.id.get());
    k.setArg(a++, slot.get());
    k.setArg(a++, max_list);
    k.setArg(a++, list.get());
    k.setArg(a++, cnt.get());
    k.setArg(a++, sum.get());
    if (coarse)
        d.launch("test.probe_coarse", k, cp.cells() * wg, wg);
    else
        d.launch("test.probe_fine", k, n, 64);
    ProbeResult r;
    r.count.resize(n);
    r.sum.resize(n);
    d.read(cnt, r.count.data(), n);
    d.read(sum, r.sum.data(), n);
    std::vector<cl_uint> all(samples.size() * max_list);
    d.read(list, all.data(), all.size());
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const std::size_t c = std::min<std::size_t>(r.count[samples[s]], max_list);
        std::vector<std::uint32_t> l(all.begin() + s * max_list, all.begin() + s * max_list + c);
        std::sort(l.begin(), l.end());
        r.lists.push_back(l);
    }
    return r;
}

// Brute force in double with absolute positions (minimum image on periodic axes). Pairs within a
// relative band of 1e-4 around the support radius are ambiguous in float and checked loosely.
struct Reference {
    std::vector<std::uint32_t> strict, loose;  // counts with r < R(1-eps) and r < R(1+eps)
    std::vector<double> sum;
    std::vector<std::set<std::uint32_t>> sure, maybe;  // for samples
};

Reference brute_force(const Particles& p, const std::vector<float>& q, double R, const Box& box,
                      std::array<bool, 3> periodic, const std::vector<std::size_t>& samples) {
    const std::size_t n = p.size();
    Reference ref;
    ref.strict.assign(n, 0);
    ref.loose.assign(n, 0);
    ref.sum.assign(n, 0.0);
    std::vector<int> slot(n, -1);
    for (std::size_t s = 0; s < samples.size(); ++s) slot[samples[s]] = static_cast<int>(s);
    ref.sure.resize(samples.size());
    ref.maybe.resize(samples.size());
    const double lo2 = R * R * (1 - 1e-4), hi2 = R * R * (1 + 1e-4);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            double r2 = 0;
            for (int k = 0; k < 3; ++k) {
                double dx = p.position[j][k] - p.position[i][k];
                if (periodic[k]) {
                    const double len = box.hi[k] - box.lo[k];
                    dx -= std::round(dx / len) * len;
                }
                r2 += dx * dx;
            }
            if (r2 < lo2) ref.strict[i]++;
            if (r2 < hi2) ref.loose[i]++;
            if (r2 < R * R) {
                const double u = 1 - r2 / (R * R);
                ref.sum[i] += q[j] * u * u * u;
            }
            if (slot[i] >= 0) {
                if (r2 < lo2) ref.sure[slot[i]].insert(p.id[j]);
                if (r2 < hi2) ref.maybe[slot[i]].insert(p.id[j]);
            }
        }
    return ref;
}

float quantity_of(std::uint32_t id) { return 0.5f + static_cast<float>(id % 17) * 0.125f; }

// Full check of one configuration on one device at one grid reach: pipeline invariants, then both
// schemes.
void check_neighbours_at(cl_rt::Device& d, const Box& box, double R, std::array<bool, 3> periodic,
                         const std::vector<std::array<double, 3>>& x, std::size_t expect_outside, std::uint64_t salt,
                         int reach) {
    CAPTURE(reach);
    Grid grid(box, R, -1, periodic, reach);
    ParticleStore ps(d, grid, x.size());
    const Particles in = make_particles(x);
    ps.upload(in);
    d.fill(ps.scratch, kPoison, 4 * ps.capacity());
    CellPipeline cp(d, grid);
    const auto res = cp.run(ps);
    CHECK(res.removed == expect_outside);
    CHECK(res.active == x.size() - expect_outside);
    const Particles out = ps.download();
    REQUIRE(out.size() == res.active);

    // Every id exactly once, with its own data; keys sorted; cell tables consistent.
    std::set<std::uint32_t> ids(out.id.begin(), out.id.end());
    CHECK(ids.size() == out.size());
    std::vector<std::uint32_t> keys(res.active), cell_key(res.cells), cell_start(res.cells + 1);
    d.read(ps.keys, keys.data(), res.active);
    d.read(cp.cell_key(), cell_key.data(), res.cells);
    d.read(cp.cell_start(), cell_start.data(), res.cells + 1);
    CHECK(std::is_sorted(keys.begin(), keys.end()));
    for (std::size_t i = 0; i < out.size(); ++i) {
        const std::size_t orig = (out.id[i] - 7) / 3;
        REQUIRE(orig < in.size());
        CHECK(out.type[i] == in.type[orig]);
        CHECK(out.density[i] == in.density[orig]);
        for (int k = 0; k < 3; ++k) CHECK(std::abs(out.position[i][k] - in.position[orig][k]) < 1e-6 * (1 + R));
    }
    CHECK(std::adjacent_find(cell_key.begin(), cell_key.end(), std::greater_equal<>()) == cell_key.end());
    if (res.cells) {
        CHECK(cell_start[0] == 0);
        CHECK(cell_start[res.cells] == res.active);
        for (std::size_t c = 0; c < res.cells; ++c) {
            REQUIRE(cell_start[c] < cell_start[c + 1]);
            CHECK(keys[cell_start[c]] == cell_key[c]);
            CHECK(keys[cell_start[c + 1] - 1] == cell_key[c]);
        }
    }

    std::vector<float> q(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) q[i] = quantity_of(out.id[i]);
    auto gen = test::rng(salt);
    std::vector<std::size_t> samples;
    for (std::size_t s = 0; s < std::min<std::size_t>(out.size(), 24); ++s) samples.push_back(gen() % out.size());
    std::sort(samples.begin(), samples.end());
    samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
    const Reference ref = brute_force(out, q, R, box, periodic, samples);

    for (bool coarse : {false, true}) {
        CAPTURE(coarse);
        const ProbeResult r = probe(d, ps, cp, grid, R, coarse, q, samples);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < out.size(); ++i) {
            const bool ok = r.count[i] >= ref.strict[i] && r.count[i] <= ref.loose[i] &&
                            std::abs(r.sum[i] - ref.sum[i]) <= 1e-4 * (1 + std::abs(ref.sum[i]));
            if (!ok && bad++ < 5)
                FAIL_CHECK("particle id " << out.id[i] << ": count " << r.count[i] << " expected ["
                                          << ref.strict[i] << ", " << ref.loose[i] << "], sum " << r.sum[i]
                                          << " expected " << ref.sum[i]);
        }
        CHECK(bad == 0);
        for (std::size_t s = 0; s < samples.size(); ++s) {
            std::set<std::uint32_t> got(r.lists[s].begin(), r.lists[s].end());
            CHECK(got.size() == r.lists[s].size());  // no neighbour twice
            CHECK(std::includes(got.begin(), got.end(), ref.sure[s].begin(), ref.sure[s].end()));
            CHECK(std::includes(ref.maybe[s].begin(), ref.maybe[s].end(), got.begin(), got.end()));
        }
    }
}

// At both grid reaches: cells of a whole support, and of half a support along a and b.
void check_neighbours(cl_rt::Device& d, const Box& box, double R, std::array<bool, 3> periodic,
                      const std::vector<std::array<double, 3>>& x, std::size_t expect_outside, std::uint64_t salt) {
    for (int reach : {1, 2}) check_neighbours_at(d, box, R, periodic, x, expect_outside, salt, reach);
}

std::vector<std::array<double, 3>> random_points(std::mt19937_64& gen, std::size_t n, const Box& b) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::array<double, 3>> x(n);
    for (auto& p : x)
        for (int k = 0; k < 3; ++k) p[k] = b.lo[k] + u(gen) * (b.hi[k] - b.lo[k]);
    return x;
}

}  // namespace

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

TEST_CASE("exchange with overlap: arrivals around a sorted middle, edges sorted alone, match the host") {
    // The layout the overlapped exchange builds (host/src/multi/slab_driver.cpp): the kept
    // particles sorted at an offset (ghosts and leavers dropped to the end of that block), arrivals
    // from the left below, from the right above, then only the edges sorted. The result must be
    // exactly the kept-in-range particles and the arrivals, sorted, each with its own data.
    const Box box{{0.0, 0.0, 0.0}, {3.0, 1.0, 1.0}};
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(131);
        Grid grid(box, 0.1);
        const GridParams g = grid.params();
        REQUIRE(grid.axis(0) == 0);
        auto column_key = [&](std::size_t c) { return static_cast<std::uint32_t>(c) << g.shift_s; };
        auto column_of = [&](std::uint32_t key) { return static_cast<std::size_t>(key >> g.shift_s); };
        // This device needs columns [4, 26); its old slab was [5, 25): arrivals from the left lie
        // below column 6, from the right at 24 and above.
        const std::size_t lo = 4, hi = 26, b_left = 6, b_right = 24;
        auto in_columns = [&](std::size_t n, double c0, double c1) {
            return random_points(gen, n, Box{{c0 * 0.1, 0.0, 0.0}, {c1 * 0.1, 1.0, 1.0}});
        };
        auto kept_x = in_columns(900, 4, 26);
        const auto leavers = in_columns(60, 1, 4), leavers_right = in_columns(60, 26, 29);
        kept_x.insert(kept_x.end(), leavers.begin(), leavers.end());
        kept_x.insert(kept_x.end(), leavers_right.begin(), leavers_right.end());
        std::shuffle(kept_x.begin(), kept_x.end(), gen);
        const auto ghosts_x = in_columns(150, 4, 26);  // stale ghosts: valid keys in pos.w, dropped anyway
        const auto left_x = in_columns(120, 4, 6), right_x = in_columns(110, 24, 26);

        std::vector<std::array<double, 3>> held = kept_x;
        held.insert(held.end(), ghosts_x.begin(), ghosts_x.end());
        Particles held_p = make_particles(held);
        const std::size_t n_kept = kept_x.size(), n_held = held.size();
        // Arrivals: ids of their own, packed as the inbox holds them.
        std::vector<float> a_pos, a_vel, a_acc;
        std::vector<std::uint32_t> a_id;
        std::map<std::uint32_t, std::array<float, 8>> expected;  // id -> pos (offset, key), velrho
        auto add_expected = [&](std::uint32_t id, std::uint32_t key, const std::array<float, 3>& off, const std::array<float, 4>& vr) {
            float k;
            std::memcpy(&k, &key, sizeof k);
            expected[id] = {off[0], off[1], off[2], k, vr[0], vr[1], vr[2], vr[3]};
        };
        for (const auto* side : {&left_x, &right_x})
            for (const auto& x : *side) {
                std::array<float, 3> off{};
                const std::uint32_t key = grid.locate(x, off);
                const std::uint32_t id = 100000 + static_cast<std::uint32_t>(a_id.size());
                const std::array<float, 4> vr{0.5f, static_cast<float>(id % 7), -1.0f, 990.0f + static_cast<float>(id % 11)};
                float k;
                std::memcpy(&k, &key, sizeof k);
                a_pos.insert(a_pos.end(), {off[0], off[1], off[2], k});
                a_vel.insert(a_vel.end(), vr.begin(), vr.end());
                a_acc.insert(a_acc.end(), {0.0f, 0.0f, -9.81f, 0.0f});
                a_id.push_back(id);
                add_expected(id, key, off, vr);
            }
        const std::size_t n_left = left_x.size(), n_right = right_x.size();
        std::size_t n_in_range = 0, x_exact = 0, y_exact = 0;
        for (std::size_t i = 0; i < n_kept; ++i) {
            std::array<float, 3> off{};
            const std::uint32_t key = grid.locate(kept_x[i], off);
            const std::size_t c = column_of(key);
            if (c < lo || c >= hi) continue;
            ++n_in_range;
            x_exact += c < b_left;
            y_exact += c >= b_right;
            add_expected(held_p.id[i], key, off, {held_p.velocity[i][0], held_p.velocity[i][1], held_p.velocity[i][2], held_p.density[i]});
        }
        // The bounds the exchange uses are upper bounds: take a few more than needed.
        std::uniform_int_distribution<std::size_t> extra(0, 20);
        const std::size_t x_bound = std::min(n_in_range, x_exact + extra(gen)), y_bound = std::min(n_in_range, y_exact + extra(gen));
        const std::size_t S = n_left, left = S + x_bound, right = S + n_in_range - y_bound;
        const std::size_t end = S + n_held + n_right, valid = n_left + n_in_range + n_right;
        REQUIRE(left < right);

        // The edges go through the reorder scratch, four arrays side by side (the exchange checks
        // the same before it takes this path).
        const std::size_t m = left + (end - right);
        ParticleStore ps(*d, grid, std::max(end, CellPipeline::edge_scratch_bytes(m) / (4 * sizeof(float)) + 1));
        ps.upload(held_p);
        d->fill(ps.scratch, kPoison, 4 * ps.capacity());
        CellPipeline cp(*d, grid);
        const KeyRange needed{column_key(lo), column_key(hi)};
        cp.enqueue_sort_keys(ps, SortSelection{n_held, 0, n_kept, n_held, needed, false});
        cp.enqueue_reorder(ps, n_held, S);
        d->fill(ps.id, kPoison, S);  // the room below must be filled by the arrivals
        ParticleArrays inbox;
        inbox.allocate(*d, n_left + n_right, "test inbox");
        d->write(inbox.pos, a_pos.data(), a_pos.size());
        d->write(inbox.velrho, a_vel.data(), a_vel.size());
        d->write(inbox.accel, a_acc.data(), a_acc.size());
        d->write(inbox.id, a_id.data(), a_id.size());
        copy_particles(*d, inbox, 0, ps, 0, n_left);
        copy_particles(*d, inbox, n_left, ps, S + n_held, n_right);
        cp.enqueue_edge_sort(ps, EdgeSort{left, right, end, S + n_in_range, S + n_held, end - right - (n_held - n_in_range), needed});
        cp.enqueue_rekey(ps, valid);
        std::vector<float> pos(4 * valid), vel(4 * valid);
        std::vector<std::uint32_t> ids(valid), keys(valid);
        d->read(ps.pos, pos.data(), 4 * valid);
        d->read(ps.velrho, vel.data(), 4 * valid);
        d->read(ps.id, ids.data(), valid);
        d->read(ps.keys, keys.data(), valid);

        REQUIRE(expected.size() == valid);
        std::set<std::uint32_t> seen;
        std::size_t wrong = 0, unsorted = 0;
        for (std::size_t i = 0; i < valid; ++i) {
            const std::uint32_t id = ids[i] & CLSPH_ID_MASK;
            std::uint32_t key;
            std::memcpy(&key, &pos[4 * i + 3], sizeof key);
            if (i > 0 && keys[i] < keys[i - 1]) ++unsorted;
            auto it = expected.find(id);
            if (keys[i] != key || it == expected.end() || !seen.insert(id).second ||
                std::memcmp(it->second.data(), &pos[4 * i], 4 * sizeof(float)) != 0 ||
                std::memcmp(it->second.data() + 4, &vel[4 * i], 4 * sizeof(float)) != 0)
                ++wrong;
        }
        INFO(n_left << " + " << n_in_range << " + " << n_right << " particles, edges [0, " << left << ") and [" << right
                    << ", " << end << ")");
        CHECK(wrong == 0);
        CHECK(unsorted == 0);
        CHECK(seen.size() == valid);
    }
}
}
