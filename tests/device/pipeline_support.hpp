// What the cell-pipeline tests (test_pipeline.cpp, test_pipeline_exchange.cpp) share: particles at given
// points, the neighbour search probed on a device and its brute-force reference.
#pragma once
#include "device/cell_pipeline.hpp"
#include "clsph/error.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

namespace pipeline_test {

using namespace clsph;
using namespace clsph::device;

inline constexpr std::uint32_t kPoison = 0xDEADBEEFu;

inline Particles make_particles(const std::vector<std::array<double, 3>>& x) {
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
inline ProbeResult probe(cl_rt::Device& d, ParticleStore& ps, CellPipeline& cp, const Grid& grid, double support, bool coarse,
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

inline Reference brute_force(const Particles& p, const std::vector<float>& q, double R, const Box& box,
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

inline float quantity_of(std::uint32_t id) { return 0.5f + static_cast<float>(id % 17) * 0.125f; }

// Full check of one configuration on one device at one grid reach: pipeline invariants, then both
// schemes.
inline void check_neighbours_at(cl_rt::Device& d, const Box& box, double R, std::array<bool, 3> periodic,
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
inline void check_neighbours(cl_rt::Device& d, const Box& box, double R, std::array<bool, 3> periodic,
                      const std::vector<std::array<double, 3>>& x, std::size_t expect_outside, std::uint64_t salt) {
    for (int reach : {1, 2}) check_neighbours_at(d, box, R, periodic, x, expect_outside, salt, reach);
}

inline std::vector<std::array<double, 3>> random_points(std::mt19937_64& gen, std::size_t n, const Box& b) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::array<double, 3>> x(n);
    for (auto& p : x)
        for (int k = 0; k < 3; ++k) p[k] = b.lo[k] + u(gen) * (b.hi[k] - b.lo[k]);
    return x;
}

}  // namespace pipeline_test
