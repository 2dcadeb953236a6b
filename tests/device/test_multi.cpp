// Several devices against one: the same particles, migration under stress, neighbours across a cut,
// and the balancer on real devices.
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

using namespace clsph;

namespace {

std::map<std::uint32_t, std::size_t> by_id(const Particles& p) {
    std::map<std::uint32_t, std::size_t> m;
    for (std::size_t i = 0; i < p.size(); ++i) m[p.id[i]] = i;
    return m;
}

// The largest position difference between two runs of the same scene, per particle id (the same
// ids must be present in both), across periodic wraps.
double largest_difference(const Scene& scene, const Particles& p, const Particles& ref) {
    const auto ids = by_id(p), ref_ids = by_id(ref);
    REQUIRE(ids.size() == p.size());  // no id twice
    double worst = 0;
    for (const auto& [id, i] : ids) {
        auto it = ref_ids.find(id);
        REQUIRE(it != ref_ids.end());  // no id lost
        for (int k = 0; k < 3; ++k) {
            double dx = p.position[i][k] - ref.position[it->second][k];
            if (scene.domain.periodic[k]) {  // the same point seen from either side of the wrap
                const double len = scene.domain.max[k] - scene.domain.min[k];
                dx -= std::round(dx / len) * len;
            }
            worst = std::max(worst, std::abs(dx));
        }
    }
    return worst;
}

// The scene on the first device alone for `steps` steps: the reference the multi-device runs match.
struct Reference {
    Particles particles;
    double time = 0;
};
Reference one_device_run(const Scene& scene, int steps) {
    Options one;
    one.devices = test::device_spec(1);
    Simulation ref(scene, one);
    for (int i = 0; i < steps; ++i) ref.step();
    Reference r{ref.particles(), ref.time()};
    REQUIRE(by_id(r.particles).size() == r.particles.size());
    return r;
}

}  // namespace

TEST_SUITE("multi") {
TEST_CASE("the same scene on 1, 2 and 3 devices gives the same particles") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);  // one device alone would compare nothing
    const double dp = 0.146 / 8;
    const Scene scene = test::small_dam(dp);
    const Reference ref = one_device_run(scene, 100);
    const Particles& pr = ref.particles;
    for (std::size_t count = 2; count <= std::min<std::size_t>(3, devs.size()); ++count) {
        CAPTURE(count);
        Options o;
        o.devices = test::device_spec(count);
        Simulation sim(scene, o);
        // The same time steps as the reference, so positions compare at equal times.
        for (int i = 0; i < 100; ++i) sim.step();
        CHECK(sim.time() == doctest::Approx(ref.time).epsilon(1e-9));
        const Particles p = sim.particles();
        REQUIRE(p.size() == pr.size());  // count (and so mass: equal masses) exact
        const double worst = largest_difference(scene, p, pr);
        MESSAGE(count << " devices: largest position difference from one device " << worst / dp << " dp");
        CHECK(worst < 1e-3 * dp);
        const auto shares = sim.shares();
        std::size_t owned = 0;
        for (const auto& s : shares) owned += s.particles;
        CHECK(owned == p.size());  // ghosts never counted as owned
    }
}

TEST_CASE("devices going idle and back give the same particles as one device") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    const double dp = 0.146 / 8;
    const Scene scene = test::small_dam(dp);
    const Reference ref = one_device_run(scene, 100);
    const Particles& pr = ref.particles;
    // Two devices: the second idle (the first steps alone, no exchange), then a split, then the
    // first idle, then a split again.
    Options o;
    o.devices = test::device_spec(2);
    testing::Seams seams;
    seams.cut_schedule = [](std::uint64_t step, std::size_t columns) {
        if (step < 25) return std::vector<std::size_t>{0, columns, columns};
        if (step < 50) return std::vector<std::size_t>{0, columns / 2, columns};
        if (step < 75) return std::vector<std::size_t>{0, 0, columns};
        return std::vector<std::size_t>{0, columns / 3, columns};
    };
    testing::set_seams(o, seams);
    Simulation sim(scene, o);
    for (int i = 0; i < 100; ++i) {
        sim.step();
        if (i == 10 || i == 60) {  // while one device is idle, it owns nothing
            const auto shares = sim.shares();
            CHECK(shares[i == 10 ? 1 : 0].particles == 0);
            CHECK(shares[i == 10 ? 1 : 0].ghosts == 0);
        }
    }
    const Particles p = sim.particles();
    REQUIRE(p.size() == pr.size());
    const double worst = largest_difference(scene, p, pr);
    MESSAGE("idle and back: largest position difference from one device " << worst / dp << " dp");
    CHECK(worst < 1e-3 * dp);
}

TEST_CASE("migration under stress: cuts move every step") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    const Scene scene = test::small_dam(0.146 / 6);
    Options o;
    o.devices = test::device_spec(std::min<std::size_t>(3, devs.size()));
    const std::size_t D = std::min<std::size_t>(3, devs.size());
    // Cuts sweep back and forth across the domain, one or two columns a step, sometimes leaving a
    // device with a single column or none at all.
    testing::Seams seams;
    seams.cut_schedule = [D](std::uint64_t step, std::size_t columns) {
        std::vector<std::size_t> c(D + 1, 0);
        c[D] = columns;
        const std::size_t span = columns;
        for (std::size_t d = 1; d < D; ++d) {
            const std::size_t phase = (step * (d + 1) + d * span / D) % (2 * span);
            c[d] = phase < span ? phase : 2 * span - phase;
        }
        std::sort(c.begin(), c.end());
        return c;
    };
    testing::set_seams(o, seams);
    Simulation sim(scene, o);
    const std::size_t n0 = sim.particles().size();
    const int steps = std::getenv("CLSPH_QUICK") ? 100 : 500;
    for (int i = 1; i <= steps; ++i) {
        sim.step();
        if (i % 50 == 0) {
            const Particles p = sim.particles();
            CAPTURE(i);
            REQUIRE(p.size() == n0);
            REQUIRE(std::set<std::uint32_t>(p.id.begin(), p.id.end()).size() == n0);
            std::size_t owned = 0;
            for (const auto& s : sim.shares()) owned += s.particles;
            REQUIRE(owned == n0);
        }
    }
    CHECK(sim.info().removed == 0);
}

TEST_CASE("a particle next to a cut sees the neighbours it sees on one device") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    const double dp = 0.146 / 8;
    const Scene scene = test::small_dam(dp);
    Options one, two;
    one.devices = test::device_spec(1);
    two.devices = test::device_spec(2);
    two.balance = BalanceMode::off;  // equal widths: the cut is in the middle of the fluid column's tank
    Simulation a(scene, one), b(scene, two);
    a.step();
    b.step();
    const Particles pa = a.particles(), pb = b.particles();
    const auto ia = by_id(pa);
    const auto shares = b.shares();
    const double cut_x = scene.domain.min[0] + static_cast<double>(shares[0].end_column) * scene.physics.support();
    std::size_t near = 0;
    for (std::size_t i = 0; i < pb.size(); ++i) {
        if (std::abs(pb.position[i][0] - cut_x) > 2 * scene.physics.support()) continue;
        const std::size_t j = ia.at(pb.id[i]);
        ++near;
        for (int k = 0; k < 3; ++k) {
            // After one step the velocity is v0 + a dt: equal accelerations, equal neighbour sets.
            CHECK(pb.velocity[i][k] == doctest::Approx(pa.velocity[j][k]).epsilon(1e-5).scale(1e-3));
        }
        CHECK(pb.density[i] == doctest::Approx(pa.density[j]).epsilon(1e-6));
    }
    MESSAGE(near << " particles within two supports of the cut at x = " << cut_x);
    CHECK(near > 20);
}
}

TEST_SUITE("multi_balance") {
TEST_CASE("a device slowed k times ends with about 1/k of the other's particles") {
    // Needs two devices of equal speed: CTest runs this suite with POCL_DEVICES="pthread pthread".
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    const int k = 3;
    // A uniform fluid slab without gravity or walls: work is proportional to particles along x,
    // so the particle shares show the balance directly.
    Scene scene;
    // ~23k particles: per-particle cost dominates pocl's fixed cost per launch, and timing noise
    // of a shared 2-core machine is small against ~50 ms force passes.
    const double dp = 0.005;
    scene.physics.dp = dp;
    scene.physics.hdp = 1.3;
    scene.physics.gravity = {0, 0, 0};
    scene.physics.c0 = 10;
    scene.domain.min = {0, 0, 0};
    scene.domain.max = {0.8, 8 * dp, 0.12};
    scene.domain.periodic = {false, true, false};
    FluidBlock f;
    f.min = {0.0, 0, 0.01};
    f.max = {0.8, 7.5 * dp, 0.1};
    scene.fluids.push_back(f);
    Options o;
    o.devices = test::device_spec(2);
    // The fine form keeps the force pass near 50 ms on pocl: with the CPU form (35x faster) pocl's
    // fixed cost per launch dominates, and the balancer rightly idles the slowed device instead.
    o.interaction = Interaction::fine;
    testing::Seams seams;
    seams.slowdown = {k, 1};
    seams.serialize_devices = true;  // both devices share the CPU: time each force pass alone
    testing::set_seams(o, seams);
    if (const char* log = std::getenv("CLSPH_BALANCE_LOG")) o.balance_log = log;
    Simulation sim(scene, o);
    std::vector<double> ratios;
    for (int i = 0; i < 80; ++i) {
        sim.step();
        if (i >= 40) {
            const auto s = sim.shares();
            ratios.push_back(double(s[0].particles) / double(s[1].particles));
        }
    }
    std::sort(ratios.begin(), ratios.end());
    const double median = ratios[ratios.size() / 2];
    const auto s = sim.shares();
    MESSAGE("slowed device " << s[0].particles << " particles, other " << s[1].particles
                             << "; median share ratio over the last 40 steps " << median << " (1/k = " << 1.0 / k << ")");
    // Measured 0.30-0.33 for k = 3. Without the balancer the ratio would stay at the initial
    // equal-work split, 1.
    CHECK(median > 0.5 / k);
    CHECK(median < 1.5 / k);
}
}
