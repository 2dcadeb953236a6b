// The probes' device stage against brute force on every device: the sums over fluid neighbours,
// water heights and wall sensors (the other stages: test_stages.cpp).
#include "cl/kernel_args.hpp"
#include "device/cell_pipeline.hpp"
#include "device/physics.hpp"
#include "probes/gauges.hpp"
#include "support/scenes.hpp"
#include "support/sph_reference.hpp"
#include "support/test_devices.hpp"
#include "stages_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace clsph;
using namespace clsph::device;
using stages_test::box_scene;
using stages_test::kSizes;

TEST_SUITE("stages") {
TEST_CASE("probes: sums over fluid neighbours match brute force") {
    Scene scene = box_scene(0.02);
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    const double h = scene.physics.h(), support = scene.physics.support();
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(504);
        Physics phys(*d, grid, scene);
        const SphParams sp = phys.params();
        CellPipeline cells(*d, grid);
        for (std::size_t n : kSizes) {
            CAPTURE(n);
            std::uniform_real_distribution<double> x(0.0, 1.0), y(0.0, 0.5), rho(980.0, 1020.0);
            Particles p;
            for (std::size_t i = 0; i < n; ++i)
                p.push_back(static_cast<std::uint32_t>(i), gen() % 3 ? ParticleType::fluid : ParticleType::boundary,
                            {0.2 * x(gen), y(gen), y(gen)}, {0, 0, 0}, static_cast<float>(rho(gen)), 0.0f);
            ParticleStore ps(*d, grid, std::max<std::size_t>(n, 1));
            ps.upload(p);
            cells.run(ps);
            const Particles sorted = ps.download();
            std::vector<std::array<double, 3>> points;
            for (int i = 0; i < 60; ++i) points.push_back({0.22 * x(gen), y(gen), y(gen)});
            points.push_back({-0.1, 0.1, 0.1});  // outside the domain: nothing
            points.push_back({0.9, 0.25, 0.25});  // no particles near
            const auto got = phys.probe(ps, cells, points);
            std::size_t wrong = 0;
            for (std::size_t q = 0; q < points.size(); ++q) {
                double s0 = 0, s1 = 0, scale0 = 0, scale1 = 0;
                for (std::size_t j = 0; j < sorted.size(); ++j) {
                    if (sorted.type[j] != ParticleType::fluid) continue;
                    double r2 = 0;
                    for (int k = 0; k < 3; ++k) r2 += (points[q][k] - sorted.position[j][k]) * (points[q][k] - sorted.position[j][k]);
                    if (r2 >= support * support || points[q][0] < 0) continue;
                    const double rh = sorted.density[j];
                    const double vw = sp.mass / rh * test::reference_w(scene.physics.kernel, h, std::sqrt(r2));
                    const double pressure = sp.eos_b * (std::pow(rh / sp.rho0, 7.0) - 1.0);
                    s0 += vw;
                    s1 += vw * pressure;
                    scale0 += std::abs(vw);
                    scale1 += std::abs(vw * pressure);
                }
                const bool ok = std::abs(got[q][0] - s0) <= 1e-4 * scale0 + 1e-6 &&
                                std::abs(got[q][1] - s1) <= 1e-3 * scale1 + 1e-3;
                if (!ok && wrong < 5)
                    MESSAGE("point " << q << ": device (" << got[q][0] << ", " << got[q][1] << "), CPU (" << s0 << ", " << s1 << ")");
                wrong += !ok;
            }
            CHECK(wrong == 0);
        }
    }
}

// The height probes' rule before issue 17: the highest z where the fraction falls through 1/2
// (walking down from the top), kept here to show what the first crossing from below changes.
static double highest_crossing(const probes::Sums* line, std::size_t n, double z0, double dz) {
    for (std::size_t k = n - 1; k > 0; --k) {
        const double f_hi = line[k][0], f_lo = line[k - 1][0];
        if (f_lo >= 0.5 && f_hi < 0.5) return z0 + dz * (static_cast<double>(k - 1) + (f_lo - 0.5) / (f_lo - f_hi));
    }
    return std::numeric_limits<double>::quiet_NaN();
}

TEST_CASE("probes: water height is the first fall through one half from below; a face is the mean of its wet points") {
    // Fractions every 0.5 m from z = 0: the wall, water, air, a drop, air.
    const std::vector<probes::Sums> line = {{0, 0}, {0.3f, 0}, {0.9f, 0}, {1, 0}, {0.8f, 0},
                                            {0.3f, 0}, {0, 0}, {0.7f, 0}, {0.2f, 0}, {0, 0}};
    CHECK(probes::water_height(line.data(), line.size(), 0.0, 0.5) == doctest::Approx(0.5 * (4 + 0.3 / 0.5)));
    CHECK(highest_crossing(line.data(), line.size(), 0.0, 0.5) == doctest::Approx(0.5 * (7 + 0.2 / 0.5)));  // the drop
    CHECK(probes::water_height(line.data() + 1, line.size() - 1, 0.5, 0.5) == doctest::Approx(2.3));  // z0 shifts it
    const std::vector<probes::Sums> dry = {{0, 0}, {0.2f, 0}, {0.49f, 0}, {0.1f, 0}};
    CHECK(probes::water_height(dry.data(), dry.size(), 0.0, 0.5) == 0.0);  // dry reads 0
    const std::vector<probes::Sums> full = {{0, 0}, {0.6f, 0}, {1, 0}, {1, 0}};
    CHECK(std::isnan(probes::water_height(full.data(), full.size(), 0.0, 0.5)));
    const std::vector<probes::Sums> half = {{0.5f, 0}, {0.25f, 0}};  // >= 1/2, then below: at the first sample
    CHECK(probes::water_height(half.data(), half.size(), 1.0, 0.5) == 1.0);
    CHECK(probes::water_height(nullptr, 0, 0.0, 0.5) == 0.0);

    // Shepard pressures 20000 (too little fluid: ignored), 1000 and 2000.
    const std::vector<probes::Sums> face = {{0.05f, 1000}, {0.5f, 500}, {0.25f, 500}};
    CHECK(probes::face_pressure(face.data(), face.size()) == doctest::Approx(1500));
    CHECK(probes::face_pressure(face.data() + 1, 1) == doctest::Approx(1000));  // a point probe
    CHECK(std::isnan(probes::face_pressure(face.data(), 1)));
}

TEST_CASE("probes: a sensor's face is a disc of points on the wall plane, its centre first") {
    Probe p;
    p.point = {0.1, 0.2, 0.3};
    p.normal = Vec3{0, -2, 1};
    p.size = 0.02;
    const double n[3] = {0, -2 / std::sqrt(5.0), 1 / std::sqrt(5.0)};
    auto check_disc = [&](const std::vector<Vec3>& pts, double spacing) {
        REQUIRE(!pts.empty());
        CHECK(pts[0] == p.point);
        double nearest = 1e300;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            double along = 0, r2 = 0;
            for (int k = 0; k < 3; ++k) {
                along += (pts[i][k] - p.point[k]) * n[k];
                r2 += (pts[i][k] - p.point[k]) * (pts[i][k] - p.point[k]);
            }
            CHECK(std::abs(along) < 1e-12);  // on the wall plane
            CHECK(std::sqrt(r2) <= 0.5 * p.size * (1 + 1e-9));  // on the disc
            if (i > 0) nearest = std::min(nearest, std::sqrt(r2));
        }
        CHECK(nearest == doctest::Approx(spacing));
    };
    // spacing min(dp/2, size/4) = 5 mm: the centre and the lattice points within 2 spacings (12).
    const auto small = probes::face_points(p, 0.01);
    CHECK(small.size() == 13);
    check_disc(small, 0.005);
    // size/4 is finer than dp/2 at dp = 0.1: the same 13 points.
    CHECK(probes::face_points(p, 0.1).size() == 13);
    // A 1 m face at dp = 1 mm: never finer than size/32, so a few hundred points, not 3 million.
    p.size = 1.0;
    const auto big = probes::face_points(p, 0.001);
    CHECK(big.size() > 700);
    CHECK(big.size() < 900);
    check_disc(big, 1.0 / 32);
    // A tiny normal is a direction like any other.
    p.size = 0.02;
    p.normal = Vec3{0, -2e-200, 1e-200};
    check_disc(probes::face_points(p, 0.01), 0.005);
    // Without a normal: the point alone.
    p.normal.reset();
    CHECK(probes::face_points(p, 0.01) == std::vector<Vec3>{p.point});
}

TEST_CASE("probes: on still water under a drop the gauge reads the water, wall sensors rho0 g depth") {
    using test::GaugeTank;
    const Scene scene = GaugeTank::scene();
    const Particles particles = scene.build_particles();  // hydrostatic: p = rho0 g (top - z) in each block
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, scene.domain.periodic);
    const probes::Points pp = probes::sample_points(scene);
    const double dp = GaugeTank::dp, rho_g = scene.physics.rho0 * 9.81;
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        Physics phys(*d, grid, scene);
        CellPipeline cells(*d, grid);
        ParticleStore ps(*d, grid, particles.size());
        ps.upload(particles);
        cells.run(ps);
        const auto sums = phys.probe(ps, cells, pp.points);
        const auto v = probes::values(scene, pp, sums);
        // The water's top particles are at `depth`; their volume ends half a spacing above.
        MESSAGE("height under the drop " << v[0] << " m, water " << GaugeTank::depth << " m");
        CHECK(std::abs(v[0] - (GaugeTank::depth + 0.5 * dp)) < 0.5 * dp);
        // The rule before read the drop's top: 0.2 m too high.
        const std::size_t line = pp.first[1] - pp.first[0];
        const double old = highest_crossing(sums.data(), line, scene.domain.min[2], pp.dz);
        MESSAGE("the highest crossing reads " << old << " m");
        CHECK(std::abs(old - (GaugeTank::drop_top + 0.5 * dp)) < 0.5 * dp);
        CHECK(v[1] == 0.0);  // in the wall: never half fluid, so dry
        const double want[3] = {rho_g * 0.05, rho_g * 0.04, rho_g * 0.05};
        for (int i = 0; i < 3; ++i) {
            CAPTURE(scene.probes[2 + i].name);
            MESSAGE(scene.probes[2 + i].name << ": " << v[2 + i] << " Pa, rho0 g depth " << want[i] << " Pa");
            CHECK(v[2 + i] == doctest::Approx(want[i]).epsilon(0.02));
        }
        // Each point of a wall sensor has fluid enough on its side of the wall.
        for (std::size_t q = pp.first[2]; q < pp.first[4]; ++q) CHECK(sums[q][0] > probes::min_fraction);
    }
}
}
