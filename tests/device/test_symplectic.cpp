// The Symplectic integrator (kernels/integrate.cl, SlabDriver::step) in whole runs: a tank at rest
// stays at rest with hydrostatic pressures, and the dam break's surge front against experiment as
// Leap-frog's. Its kernels against plain C++: the stages suite; 1, 2 and 3 devices bitwise:
// multi_bitwise.
#include "clsph/simulation.hpp"
#include "support/scenes.hpp"
#include "support/surge_front.hpp"
#include "support/test_devices.hpp"
#include "support/validation.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace clsph;

TEST_SUITE("symplectic") {
TEST_CASE("Symplectic: a tank at rest stays at rest, its pressures hydrostatic") {
    Scene s;
    const double dp = 0.025, H = 0.3, W = 0.3, D = 8 * dp;
    s.physics.dp = dp;
    s.physics.hdp = 1.3;
    s.physics.alpha = 0.1;
    s.physics.integrator = Integrator::symplectic;
    s.domain.min = {-3 * dp, 0, -3 * dp};
    s.domain.max = {W + 3 * dp, D, 0.45};
    s.domain.periodic = {false, true, false};
    BoxWalls w;
    w.min = {0, 0, 0};
    w.max = {W, D - dp, 0.45};
    w.faces = x_min | x_max | z_min;
    s.walls.push_back(w);
    FluidBlock f;
    f.max = {W, D - 0.5 * dp, H};
    s.fluids.push_back(f);
    for (double depth : {0.075, 0.15, 0.225}) {
        Probe p;
        p.name = "p" + std::to_string(int(depth * 1000));
        p.point = {W / 2, D / 2, H - depth};
        s.probes.push_back(p);
    }
    Simulation sim(s, test::validation_options());
    double ke_peak = 0;
    sim.run_until(std::getenv("CLSPH_QUICK") ? 0.1 : 0.3,
                  [&](const StepInfo& i) { ke_peak = std::max(ke_peak, i.kinetic_energy); });
    MESSAGE("symplectic tank: " << sim.info().step << " steps, kinetic energy peak " << ke_peak << " J, end "
                                << sim.info().kinetic_energy << " J");
    CHECK(sim.info().kinetic_energy < 0.75 * ke_peak);
    CHECK(sim.info().removed == 0);
    const auto probes = sim.sample_probes();
    for (std::size_t i = 0; i < 3; ++i) MESSAGE(probes[i].name << ": " << probes[i].value << " Pa");
    // Hydrostatic: the pressure grows by rho0 g per metre of depth (the surface's exact height is a
    // matter of half a spacing), linearly.
    const double rise = probes[2].value - probes[0].value, expect = s.physics.rho0 * 9.81 * 0.15;
    MESSAGE("from 0.075 to 0.225 m deep: " << rise << " Pa, rho0 g 0.15 m = " << expect << " Pa");
    CHECK(rise == doctest::Approx(expect).epsilon(0.03));
    CHECK(probes[1].value == doctest::Approx(0.5 * (probes[0].value + probes[2].value)).epsilon(0.02));
}

TEST_CASE("Symplectic: dam break surge front against Koshizuka & Oka (1996), as Leap-frog's") {
    const double L = 0.146;
    Scene s = test::surge_dam_break(L, L / 20);
    s.physics.integrator = Integrator::symplectic;
    Simulation sim(s, test::validation_options());
    CHECK(test::surge_front_rms(sim, L) <= 0.10);
}
}
