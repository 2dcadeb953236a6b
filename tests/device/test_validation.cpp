// Whole simulations: conservation, a hydrostatic tank, the dam break against experiment, and a
// forced blow-up. Long runs use one device (pocl's threaded CPU device in CI).
#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "support/scenes.hpp"
#include "support/surge_front.hpp"
#include "support/test_devices.hpp"
#include "support/validation.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace clsph;

namespace {

std::array<double, 3> momentum(const Particles& p, double m) {
    std::array<double, 3> P{0, 0, 0};
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int k = 0; k < 3; ++k) P[k] += m * p.velocity[i][k];
    return P;
}

Scene dam_break(double L, double dp) { return test::surge_dam_break(L, dp); }

}  // namespace

TEST_SUITE("validation") {
TEST_CASE("an isolated fluid block without gravity conserves mass and momentum") {
    Scene s;
    s.physics.dp = 0.02;
    s.physics.gravity = {0, 0, 0};
    s.physics.c0 = 10.0;
    s.domain.min = {-1, -1, -1};
    s.domain.max = {1, 1, 1};
    FluidBlock f;
    f.min = {-0.2, -0.15, -0.1};
    f.max = {0.2, 0.15, 0.1};
    f.velocity = {0.3, -0.1, 0.05};
    s.fluids.push_back(f);
    Simulation sim(s, test::validation_options());
    const double m = s.physics.rho0 * std::pow(s.physics.dp, 3);
    Particles p0 = sim.particles();
    const auto P0 = momentum(p0, m);
    double sum_abs = 0;
    for (const auto& v : p0.velocity) sum_abs += m * (std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]));
    for (int i = 0; i < 60; ++i) sim.step();
    const Particles p1 = sim.particles();
    CHECK(p1.size() == p0.size());  // mass: every particle (of equal mass) is still there
    CHECK(sim.info().removed == 0);
    const auto P1 = momentum(p1, m);
    for (int k = 0; k < 3; ++k) {
        CAPTURE(k);
        CHECK(std::abs(P1[k] - P0[k]) < 1e-5 * sum_abs);  // round-off only: pair forces are antisymmetric
    }
    // It did something: the block expands from its hydrostatic-free start (pressure 0) only a bit,
    // but particles moved.
    CHECK(sim.time() > 0);
}

TEST_CASE("hydrostatic tank: probe pressures match rho0 g depth") {
    // A periodic slice of a tank 0.3 m wide with water 0.3 m deep (12 particles), h = 1.3 dp so
    // CI affords it; settled for 0.6 s (about 70 sound crossings of the depth).
    Scene s;
    s.name = "hydrostatic";
    const double dp = 0.025, H = 0.3, W = 0.3, D = 8 * dp;
    s.physics.dp = dp;
    s.physics.hdp = 1.3;
    s.physics.alpha = 0.1;  // a settling tank: more damping than a flow, so it settles within CI's budget
    s.domain.min = {-3 * dp, 0, -3 * dp};
    s.domain.max = {W + 3 * dp, D, 0.45};
    s.domain.periodic = {false, true, false};
    BoxWalls w;
    w.min = {0, 0, 0};
    w.max = {W, D, 0.45};
    w.faces = x_min | x_max | z_min;
    s.walls.push_back(w);
    FluidBlock f;
    f.min = {0, 0, 0};
    f.max = {W, D - 0.5 * dp, H};
    s.fluids.push_back(f);
    for (double depth : {0.075, 0.15, 0.225}) {
        Probe p;
        p.name = "p_depth_" + std::to_string(depth);  // probe names are file names: no spaces
        p.point = {W / 2, D / 2, H - depth};
        s.probes.push_back(p);
    }
    Probe hp;
    hp.kind = Probe::Kind::height;
    hp.name = "height";
    hp.point = {W / 2, D / 2, 0};
    s.probes.push_back(hp);
    Simulation sim(s, test::validation_options());
    double ke_peak = 0;
    sim.run_until(std::getenv("CLSPH_QUICK") ? 0.12 : 0.6,
                  [&](const StepInfo& i) { ke_peak = std::max(ke_peak, i.kinetic_energy); });
    const double ke_end = sim.info().kinetic_energy;
    MESSAGE("hydrostatic: " << sim.info().particles << " particles, " << sim.info().step << " steps in "
                            << sim.info().wall_seconds << " s; kinetic energy peak " << ke_peak << " J, at the end "
                            << ke_end << " J");
    CHECK(ke_end < 0.75 * ke_peak);  // the start-up transient decays
    const auto probes = sim.sample_probes();
    const double height = probes[3].value;
    // The fluid fraction falls through 1/2 half a spacing above the top particles' centres.
    MESSAGE("water height " << height << " m (top particles at " << H << ")");
    CHECK(height == doctest::Approx(H + 0.5 * dp).epsilon(0.02));
    for (int i = 0; i < 3; ++i) {
        // depth measured from the surface the height probe finds.
        const double depth = height - s.probes[i].point[2];
        const double expect = s.physics.rho0 * 9.81 * depth;
        MESSAGE(probes[i].name << ": " << probes[i].value << " Pa, rho0 g depth = " << expect << " Pa");
        CHECK(probes[i].value == doctest::Approx(expect).epsilon(0.03));
    }
    // No fluid particle crossed a wall.
    const auto p = sim.particles();
    CHECK(sim.info().removed == 0);
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.type[i] == ParticleType::fluid) {
            CHECK(p.position[i][0] > 0.0);
            CHECK(p.position[i][0] < W);
            CHECK(p.position[i][2] > 0.0);
        }
}

TEST_CASE("gauges on still water, sampled every step: the height ignores a drop above, wall sensors read rho0 g depth") {
    using test::GaugeTank;
    Scene s = GaugeTank::scene();
    s.run.probe_every = 1;  // every step a probe step: the step ahead samples each in the queue
    Options o = test::validation_options();
    o.synchronous = false;  // the harder path: sample_probes() inside the callback, steps in flight
    Simulation sim(s, o);
    const double dp = GaugeTank::dp, rho_g = s.physics.rho0 * 9.81;
    auto height_ok = [&](double h) { return std::abs(h - (GaugeTank::depth + 0.5 * dp)) < 0.5 * dp; };

    // t = 0, the hydrostatic start: the sensors' and the point's depths are 0.05, 0.04 and 0.05 m.
    const auto v0 = sim.sample_probes();
    REQUIRE(v0.size() == 5);
    MESSAGE("t = 0: height " << v0[0].value << " m; " << v0[2].value << ", " << v0[3].value << ", " << v0[4].value << " Pa");
    CHECK(height_ok(v0[0].value));
    CHECK(v0[1].value == 0.0);  // the dry gauge reads 0, not NaN
    CHECK(v0[2].value == doctest::Approx(rho_g * 0.05).epsilon(0.02));
    CHECK(v0[3].value == doctest::Approx(rho_g * 0.04).epsilon(0.02));
    CHECK(v0[4].value == doctest::Approx(rho_g * 0.05).epsilon(0.02));

    // Then every step, while the drop falls (it reaches the water at about 0.17 s). The pressures
    // swing by tens of per cent in these first steps, at the walls and mid-tank alike (the walls'
    // start-up sends sound waves across the tank), so they are only required to be there.
    std::size_t samples = 0, wrong_height = 0, dry_sensor = 0;
    double height_lo = 1e300, height_hi = -1e300;
    sim.run_until(0.03, [&](const StepInfo& info) {
        const auto v = sim.sample_probes();
        ++samples;
        CHECK(v[0].time == info.time);
        height_lo = std::min(height_lo, v[0].value);
        height_hi = std::max(height_hi, v[0].value);
        wrong_height += !height_ok(v[0].value);
        dry_sensor += !std::isfinite(v[2].value) || !std::isfinite(v[3].value);
    });
    MESSAGE("gauges: " << samples << " samples in " << sim.info().step << " steps; height " << height_lo << " to "
                       << height_hi << " m");
    CHECK(samples == sim.info().step);
    CHECK(wrong_height == 0);
    CHECK(dry_sensor == 0);
    // The drop is still in the air, its top far above the water: the highest crossing of 1/2 (the
    // rule before) would have read about there (test_stages.cpp shows it on the same scene).
    const Particles p = sim.particles();
    double top = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.type[i] == ParticleType::fluid && std::abs(p.position[i][0] - 0.1) < dp && std::abs(p.position[i][1] - 0.08) < dp)
            top = std::max(top, p.position[i][2]);
    MESSAGE("the drop's top above the gauge at " << top << " m");
    CHECK(top > GaugeTank::depth + 0.15);
}

TEST_CASE("dam break surge front against Koshizuka & Oka (1996)") {
    const double L = 0.146;
    Simulation sim(dam_break(L, L / 20), test::validation_options());
    CHECK(test::surge_front_rms(sim, L) <= 0.10);
}

TEST_CASE("a blow-up stops with a typed error naming step, time and particle") {
    Scene s = dam_break(0.146, 0.146 / 10);
    s.run.fixed_dt = 2e-3;  // about 15 times the CFL step
    Simulation sim(s, test::validation_options());
    try {
        for (int i = 0; i < 200; ++i) sim.step();
        FAIL("no error after 200 oversized steps");
    } catch (const SimulationError& e) {
        const std::string what = e.what();
        MESSAGE(what);
        CHECK(what.find("step ") != std::string::npos);
        CHECK(what.find("particle ") != std::string::npos);
        CHECK(what.find("t = ") != std::string::npos);
    }
    // The last good state is kept and is finite.
    const Particles& good = sim.last_good();
    REQUIRE(good.size() > 0);
    for (std::size_t i = 0; i < good.size(); ++i) REQUIRE(std::isfinite(good.velocity[i][0]));
}
}
