// Set-up on the device (kernels/generate.cl, device/generate.cpp, scene/lattice_plan.cpp): on
// random scenes of walls, solid boxes and fluid blocks (random dp, offsets off the lattice, faces,
// layers, split axis), the lattice plan against the point-by-point host sampler, and every
// device's particles for slabs cut anywhere (through blocks) against the plan's host particles,
// bit for bit, with poisoned stores; whole runs set up on the devices against runs set up on the
// host.
#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "device/generate.hpp"
#include "device/memory_census.hpp"
#include "scene/lattice.hpp"
#include "scene/lattice_plan.hpp"
#include "support/scenes.hpp"
#include "support/skip.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <tuple>

using namespace clsph;

namespace {

double uniform(std::mt19937_64& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
int pick(std::mt19937_64& rng, int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }

// A tank (some faces), up to two solid boxes and up to three fluid blocks, none on the lattice.
Scene random_scene(std::mt19937_64& rng) {
    for (;;) {
        Scene s;
        const double dp = uniform(rng, 0.008, 0.016);
        s.physics.dp = dp;
        s.physics.hdp = pick(rng, 0, 1) ? 2.0 : 1.3;
        s.physics.coefsound = 10;
        const Vec3 o{uniform(rng, -0.05, 0.05), uniform(rng, -0.05, 0.05), uniform(rng, -0.05, 0.05)};
        const Vec3 len{uniform(rng, 0.12, 0.3), uniform(rng, 0.06, 0.16), uniform(rng, 0.1, 0.25)};
        BoxWalls w;
        w.min = o;
        for (int k = 0; k < 3; ++k) w.max[k] = o[k] + len[k];
        w.faces = static_cast<unsigned>(pick(rng, 0, 63)) | z_min;
        w.layers = pick(rng, 1, 3);
        s.walls.push_back(w);
        for (int k = 0; k < 3; ++k) {
            s.domain.min[k] = o[k] - 4 * dp;
            s.domain.max[k] = o[k] + len[k] + 4 * dp;
        }
        s.domain.split_axis = pick(rng, -1, 2);
        for (int b = pick(rng, 0, 2); b > 0; --b) {
            SolidBox box;
            for (int k = 0; k < 3; ++k) {
                box.min[k] = o[k] + uniform(rng, 0.1, 0.6) * len[k];
                box.max[k] = std::min(box.min[k] + uniform(rng, 0.02, 0.08), o[k] + len[k]);
            }
            box.layers = pick(rng, 0, 3);
            s.solids.push_back(box);
        }
        for (int f = pick(rng, 1, 3); f > 0; --f) {
            FluidBlock block;
            for (int k = 0; k < 3; ++k) {
                block.min[k] = o[k] + uniform(rng, 0.0, 0.5) * len[k];
                block.max[k] = std::min(block.min[k] + uniform(rng, 0.2, 0.6) * len[k], o[k] + len[k]);
                block.velocity[k] = uniform(rng, -0.5, 0.5);
            }
            if (pick(rng, 0, 1)) block.surface = block.max[2] + uniform(rng, 0.0, 0.05);
            s.fluids.push_back(block);
        }
        try {
            (void)scene::LatticePlan::make(s);
            return s;
        } catch (const SceneError&) {  // every fluid point inside a box: draw again
        }
    }
}

using Key = std::tuple<double, double, double, int>;
std::map<Key, std::size_t> by_position(const Particles& p) {
    std::map<Key, std::size_t> m;
    for (std::size_t i = 0; i < p.size(); ++i)
        m.emplace(Key{p.position[i][0], p.position[i][1], p.position[i][2], static_cast<int>(p.type[i])}, i);
    return m;
}

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

}  // namespace

TEST_SUITE("generate") {
TEST_CASE("the lattice plan gives the host sampler's particles: positions, types, densities, velocities") {
    auto rng = test::rng(0x6e01);
    for (int round = 0; round < 12; ++round) {
        const Scene s = random_scene(rng);
        const auto plan = scene::LatticePlan::make(s);
        const Particles a = plan.particles(), b = scene::sampled_particles(s);
        INFO("round " << round << ", dp " << s.physics.dp << ", " << s.solids.size() << " boxes, " << s.fluids.size()
                      << " blocks, split axis " << plan.split_axis);
        REQUIRE(a.size() == b.size());
        CHECK(a.size() == plan.count());
        // Ids 0..n-1, boundaries first.
        for (std::size_t i = 0; i < a.size(); ++i) {
            REQUIRE(a.id[i] == i);
            REQUIRE((a.type[i] == ParticleType::boundary) == (i < plan.boundary_count));
        }
        const auto mb = by_position(b);
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < a.size(); ++i) {
            const auto it = mb.find(Key{a.position[i][0], a.position[i][1], a.position[i][2], static_cast<int>(a.type[i])});
            if (it == mb.end()) {
                ++mismatches;
                continue;
            }
            const std::size_t j = it->second;
            mismatches += bits(a.density[i]) != bits(b.density[j]) || bits(a.pressure[i]) != bits(b.pressure[j]) ||
                          a.velocity[i] != b.velocity[j];
        }
        CHECK(mismatches == 0);
    }
}

TEST_CASE("the memory model's census from the plan: the particles' own per column, cells an upper bound") {
    auto rng = test::rng(0x6e03);
    for (int round = 0; round < 8; ++round) {
        const Scene s = random_scene(rng);
        const auto plan = scene::LatticePlan::make(s);
        const auto a = detail::census_of(s, plan), b = detail::census_of(s, plan.particles());
        INFO("round " << round);
        CHECK(a.particles == b.particles);
        CHECK(a.per_column == b.per_column);
        CHECK(a.boundary_per_column == b.boundary_per_column);
        CHECK(a.max_boundary_id == b.max_boundary_id);
        std::size_t ca = 0, cb = 0, below = 0;
        for (std::size_t c = 0; c < a.cells_per_column.size(); ++c) {
            ca += a.cells_per_column[c];
            cb += b.cells_per_column[c];
            below += a.cells_per_column[c] < b.cells_per_column[c];
        }
        CHECK(below == 0);
        CHECK(static_cast<double>(ca) <= 1.1 * static_cast<double>(cb) + 8);
    }
}

TEST_CASE("set-up on every device: each slab's particles equal the host's bit for bit, slabs cut through blocks") {
    auto rng = test::rng(0x6e02);
    for (auto* dev : test::devices()) {
        INFO("device " << dev->label());
        for (int round = 0; round < 4; ++round) {
            const Scene s = random_scene(rng);
            const auto plan = scene::LatticePlan::make(s);
            const device::Grid grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), s.domain.split_axis,
                                    s.domain.periodic, device::reach_for(s.physics.support(), s.physics.dp));
            const std::size_t columns = grid.params().n_s;
            std::vector<std::size_t> cuts{0, columns};
            for (int c = pick(rng, 0, 3); c > 0; --c) cuts.push_back(static_cast<std::size_t>(pick(rng, 0, static_cast<int>(columns))));
            std::sort(cuts.begin(), cuts.end());
            std::vector<char> seen(plan.count(), 0);
            std::size_t total = 0;
            device::Generator gen(*dev, grid);
            for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
                const Particles host = device::slab_particles(plan, grid, cuts[k], cuts[k + 1]);
                INFO("round " << round << ", columns [" << cuts[k] << ", " << cuts[k + 1] << ") of " << columns << ": "
                              << host.size() << " particles");
                const std::size_t cap = host.size() + 17;
                device::ParticleStore store(*dev, grid, cap);
                const float nan = std::numeric_limits<float>::quiet_NaN();
                dev->fill(store.pos, nan, 4 * cap);
                dev->fill(store.velrho, nan, 4 * cap);
                dev->fill(store.accel, nan, 4 * cap);
                dev->fill(store.id, std::uint32_t{0xdeadbeefu}, cap);
                const std::size_t n = gen.generate(plan, store, cuts[k], cuts[k + 1]);
                REQUIRE(n == host.size());
                REQUIRE(store.ranges.owned == n);
                std::vector<float> pos(4 * cap), vr(4 * cap), acc(4 * cap);
                std::vector<std::uint32_t> id(cap);
                dev->read(store.pos, pos.data(), 4 * cap);
                dev->read(store.velrho, vr.data(), 4 * cap);
                dev->read(store.accel, acc.data(), 4 * cap);
                dev->read(store.id, id.data(), cap);
                std::size_t bad = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    std::array<float, 3> off{};
                    const std::uint32_t key = grid.locate(host.position[i], off);
                    const std::uint32_t word = host.id[i] | (static_cast<std::uint32_t>(host.type[i]) << CLSPH_TYPE_SHIFT);
                    bool ok = bits(pos[4 * i + 3]) == key && id[i] == word && bits(vr[4 * i + 3]) == bits(host.density[i]);
                    for (int a = 0; a < 3; ++a)
                        ok = ok && bits(pos[4 * i + a]) == bits(off[a]) && bits(vr[4 * i + a]) == bits(host.velocity[i][a]) &&
                             acc[4 * i + a] == 0.0f;
                    ok = ok && acc[4 * i + 3] == 0.0f;
                    if (!ok && bad++ < 3)
                        MESSAGE("particle " << i << ": id word " << id[i] << " (host " << word << "), key "
                                            << bits(pos[4 * i + 3]) << " (host " << key << ")");
                    if (host.id[i] < seen.size()) seen[host.id[i]] += 1;
                }
                CHECK(bad == 0);
                std::size_t untouched = 0;  // nothing written past the slab's particles
                for (std::size_t i = n; i < cap; ++i) untouched += id[i] == 0xdeadbeefu && std::isnan(pos[4 * i]);
                CHECK(untouched == cap - n);
                total += n;
            }
            CHECK(total == plan.count());
            CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<std::ptrdiff_t>(plan.count()));
        }
    }
}

TEST_CASE("a run set up on the devices is bitwise the run set up on the host (one and two devices, DBC and mDBC)") {
    for (const bool mdbc : {false, true}) {
        Scene s = test::small_dam(0.146 / 8);
        if (mdbc) s.boundary_method = BoundaryMethod::mdbc;
        for (std::size_t count : {std::size_t{1}, std::size_t{2}}) {
            if (count > test::devices().size()) {
                test_skip::skip("generate on " + std::to_string(count) + " devices: " + std::to_string(test::devices().size()) + " available");
                continue;
            }
            INFO((mdbc ? "mDBC" : "DBC") << " on " << count << " devices");
            std::vector<Particles> out;
            for (const bool on_device : {true, false}) {
                Options o;
                o.devices = test::device_spec(count);
                o.setup_on_device = on_device;
                o.balance = BalanceMode::fixed;  // the same cuts for both (no calibration timing)
                Simulation sim(s, o);
                for (int k = 0; k < 20; ++k) sim.step();
                out.push_back(sim.particles());
            }
            REQUIRE(out[0].size() == out[1].size());

            std::size_t differ = 0;
            for (std::size_t i = 0; i < out[0].size(); ++i)
                differ += out[0].id[i] != out[1].id[i] || out[0].position[i] != out[1].position[i] ||
                          bits(out[0].density[i]) != bits(out[1].density[i]);
            CHECK(differ == 0);
        }
    }
}
}

TEST_SUITE("generate") {
TEST_CASE("thinned downloads: every K-th particle by id and boxes, selected on the devices, equal the full download's") {
    for (std::size_t count : {std::size_t{1}, std::size_t{2}}) {
        if (count > test::devices().size()) {
            test_skip::skip("generate on " + std::to_string(count) + " devices: " + std::to_string(test::devices().size()) + " available");
            continue;
        }
        Options o;
        o.devices = test::device_spec(count);
        o.balance = BalanceMode::fixed;
        Simulation sim(test::small_dam(0.146 / 8), o);
        for (int k = 0; k < 5; ++k) sim.step();
        const Particles all = sim.particles();
        // Boxes: the left of the column, one across the tank's middle (no particle at first), one
        // outside the domain; with and without a stride.
        const std::vector<std::optional<std::array<double, 6>>> boxes = {
            std::nullopt, std::array<double, 6>{-1, -1, -1, 0.07, 1, 0.1}, std::array<double, 6>{0.2, -1, -1, 0.25, 1, 1},
            std::array<double, 6>{5, 5, 5, 6, 6, 6}};
        for (const auto& box : boxes)
        for (std::uint32_t stride : {1u, 2u, 3u, 7u, 1000000u}) {
            if (stride == 1 && !box) continue;
            INFO(count << " devices, stride " << stride << (box ? ", a box" : ""));
            const Particles thin = sim.particles(Simulation::Selection{stride, box});
            auto inside = [&](const Vec3& x) {
                if (!box) return true;
                const auto& b = *box;
                return x[0] >= b[0] && x[1] >= b[1] && x[2] >= b[2] && x[0] <= b[3] && x[1] <= b[4] && x[2] <= b[5];
            };
            std::size_t j = 0, differ = 0;
            for (std::size_t i = 0; i < all.size(); ++i) {
                if (all.id[i] % stride != 0 || !inside(all.position[i])) continue;
                if (j >= thin.size()) {
                    ++differ;
                    continue;
                }
                differ += thin.id[j] != all.id[i] || thin.type[j] != all.type[i] || thin.position[j] != all.position[i] ||
                          thin.velocity[j] != all.velocity[i] || bits(thin.density[j]) != bits(all.density[i]) ||
                          bits(thin.pressure[j]) != bits(all.pressure[i]);
                ++j;
            }
            CHECK(j == thin.size());
            CHECK(differ == 0);
        }
    }
}
}
