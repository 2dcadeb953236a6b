// Open boundaries' device stages (kernels/inlets.cl, kernels/outlets.cl) against plain C++ on
// random particles, on every device, outputs poisoned: an inlet's buffer velocity with a profile
// (direction * speed * the nearest lattice point's factor) and no acceleration in either buffer;
// an outlet zone's density held to Tait's for its pressure or for the hydrostatic pressure below
// its level, with no drho/dt; the fluid past a zone's face marked so that the cell pass removes
// and counts it, and nothing else.
#include "device/cell_pipeline.hpp"
#include "device/inlet_zones.hpp"
#include "device/outlet_zones.hpp"
#include "scene/open_boundaries.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

using namespace clsph;
using namespace clsph::device;

namespace {

constexpr double kDp = 0.01;

// A domain 0.4 x 0.2 x 0.3 m off the origin, zero to three zones in it.
Scene zone_scene() {
    Scene s;
    s.physics.dp = kDp;
    s.physics.hdp = 1.3;
    s.physics.gravity = {0, 0, -9.81};
    s.physics.c0 = 15.0;
    s.domain.min = {-0.05, -0.02, -0.1};
    s.domain.max = {0.35, 0.18, 0.2};
    return s;
}

Particles random_particles(std::mt19937_64& gen, const Scene& s, std::size_t n) {
    std::uniform_real_distribution<double> u01(0.0, 1.0), vel(-1.0, 1.0), rho(980.0, 1040.0);
    Particles p;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 x{};
        for (int k = 0; k < 3; ++k) x[k] = s.domain.min[k] + u01(gen) * (s.domain.max[k] - s.domain.min[k]);
        p.push_back(static_cast<std::uint32_t>(i), u01(gen) < 0.2 ? ParticleType::boundary : ParticleType::fluid, x,
                    {float(vel(gen)), float(vel(gen)), float(vel(gen))}, float(rho(gen)), 0.0f);
    }
    return p;
}

// Within `margin` of one of a box's faces (where float and double may disagree on the side).
bool near_faces(const Vec3& x, const Vec3& lo, const Vec3& hi, double margin) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(x[k] - lo[k]) < margin || std::abs(x[k] - hi[k]) < margin) return true;
    return false;
}

bool inside(const Vec3& x, const Vec3& lo, const Vec3& hi) {
    for (int k = 0; k < 3; ++k)
        if (x[k] < lo[k] || x[k] >= hi[k]) return false;
    return true;
}

std::vector<float> random_words(std::mt19937_64& gen, std::size_t n) {
    std::uniform_real_distribution<float> a(-50.0f, 50.0f);
    std::vector<float> w(n);
    for (auto& x : w) x = a(gen);
    return w;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_SUITE("open_boundaries") {
TEST_CASE("an inlet's buffer: direction * speed * the profile's factor, no acceleration, as plain C++ has it") {
    Scene s = zone_scene();
    Inlet a;  // along -x, a profile in z
    a.min = {0.2, 0.0, 0.0};
    a.max = {0.3, 0.1, 0.1};
    a.velocity = {-1, 0, 0};
    a.speed.time = {0.0, 1.0};
    a.speed.value = {0.3, 0.9};
    a.profile.axis = 2;
    a.profile.points = {{0.0, 0.2}, {0.05, 1.0}, {0.1, 0.6}};
    Inlet b;  // along +y, uniform
    b.min = {0.0, 0.0, 0.12};
    b.max = {0.1, 0.06, 0.18};
    b.velocity = {0, 0.4, 0};
    s.inlets = {a, b};
    s.validate();
    auto gen = test::rng(3401);
    const Particles p = random_particles(gen, s, 6000);
    std::uniform_real_distribution<double> speed(0.0, 2.0);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support());
        ParticleStore ps(*d, grid, p.size());
        ps.upload(p);
        InletZones zones(*d, grid, s);
        for (bool after_forces : {true, false}) {
            CAPTURE(after_forces);
            const std::size_t n = p.size();
            const std::vector<float> v0 = random_words(gen, 4 * n), a0 = random_words(gen, 4 * n);
            const float poison = std::numeric_limits<float>::quiet_NaN();
            std::vector<float> s0(4 * n, poison);  // the pass's own accelerations: poisoned
            d->write(ps.velrho, v0.data(), v0.size());
            d->write(ps.accel, a0.data(), a0.size());
            d->write(ps.scratch, s0.data(), s0.size());
            const std::vector<double> speeds{speed(gen), speed(gen)};
            zones.impose(ps, speeds, after_forces);
            std::vector<float> v(4 * n), acc(4 * n), sc(4 * n);
            d->read(ps.velrho, v.data(), v.size());
            d->read(ps.accel, acc.data(), acc.size());
            d->read(ps.scratch, sc.data(), sc.size());
            std::size_t bad = 0, in_a = 0, in_b = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3& x = p.position[i];
                if (near_faces(x, a.min, a.max, 1e-5) || near_faces(x, b.min, b.max, 1e-5)) continue;
                const bool fluid = p.type[i] == ParticleType::fluid;
                const int box = !fluid ? -1 : inside(x, a.min, a.max) ? 0 : inside(x, b.min, b.max) ? 1 : -1;
                std::array<double, 3> want{};
                if (box == 0) {  // the lattice point nearest in z, its factor from the points
                    const double z = std::round(x[2] / kDp) * kDp;
                    const double f = z <= 0.05 ? 0.2 + (1.0 - 0.2) * z / 0.05 : 1.0 + (0.6 - 1.0) * (z - 0.05) / 0.05;
                    want = {-speeds[0] * f, 0, 0};
                    ++in_a;
                } else if (box == 1) {
                    want = {0, speeds[1], 0};
                    ++in_b;
                }
                for (int k = 0; k < 4; ++k) {
                    const std::size_t w = 4 * i + static_cast<std::size_t>(k);
                    bool ok;
                    if (box < 0 || k == 3)
                        ok = same_bits(v[w], v0[w]) && same_bits(acc[w], a0[w]) && (after_forces ? same_bits(sc[w], s0[w]) : true);
                    else
                        ok = std::abs(v[w] - want[static_cast<std::size_t>(k)]) <= 2e-6 * (1 + std::abs(want[static_cast<std::size_t>(k)])) &&
                             acc[w] == 0.0f && (after_forces ? sc[w] == 0.0f : same_bits(sc[w], s0[w]));
                    if (!ok && bad++ < 8)
                        FAIL_CHECK("particle " << i << " (box " << box << ") component " << k << ": velocity " << v[w] << ", accel "
                                               << acc[w] << ", new accel " << sc[w]);
                }
            }
            CHECK(bad == 0);
            CHECK(in_a > 50);
            CHECK(in_b > 20);
        }
    }
}

TEST_CASE("outlet zones: density held to Tait's for the pressure or the level, no drho/dt, as plain C++ has it") {
    Scene s = zone_scene();
    Outlet level;  // a level in time: 0.12 m at t = 0 to 0.02 m at t = 1
    level.zone = true;
    level.axis = 0;
    level.upper = true;
    level.min = {0.2, 0.0, -0.05};
    level.max = {0.3, 0.15, 0.18};
    level.level_series.time = {0.0, 1.0};
    level.level_series.value = {0.12, 0.02};
    Outlet pressure;
    pressure.zone = true;
    pressure.axis = 2;
    pressure.upper = false;
    pressure.min = {-0.04, 0.0, 0.0};
    pressure.max = {0.1, 0.1, 0.1};
    pressure.pressure = 350.0;
    Outlet face;  // a face of the domain: no zone
    face.axis = 1;
    s.outlets = {face, level, pressure};
    s.validate();
    auto gen = test::rng(3402);
    const Particles p = random_particles(gen, s, 6000);
    const double c0 = s.sound_speed(), rho0 = s.physics.rho0, B = c0 * c0 * rho0 / s.physics.gamma, g = 9.81;
    auto tait = [&](double pr) { return rho0 * std::pow(1.0 + pr / B, 1.0 / s.physics.gamma); };
    std::uniform_real_distribution<double> when(0.0, 1.2);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support());
        ParticleStore ps(*d, grid, p.size());
        ps.upload(p);
        OutletZones zones(*d, grid, s);
        for (int round = 0; round < 3; ++round) {
            const std::size_t n = p.size();
            const std::vector<float> v0 = random_words(gen, 4 * n), a0 = random_words(gen, 4 * n), s0 = random_words(gen, 4 * n);
            d->write(ps.velrho, v0.data(), v0.size());
            d->write(ps.accel, a0.data(), a0.size());
            d->write(ps.scratch, s0.data(), s0.size());
            const double t = when(gen), lvl = t >= 1.0 ? 0.02 : 0.12 - 0.1 * t;
            CAPTURE(t);
            zones.hold(ps, t);
            std::vector<float> v(4 * n), acc(4 * n), sc(4 * n);
            d->read(ps.velrho, v.data(), v.size());
            d->read(ps.accel, acc.data(), acc.size());
            d->read(ps.scratch, sc.data(), sc.size());
            std::size_t bad = 0, held = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3& x = p.position[i];
                if (near_faces(x, level.min, level.max, 1e-5) || near_faces(x, pressure.min, pressure.max, 1e-5)) continue;
                const bool fluid = p.type[i] == ParticleType::fluid;
                double want = -1;  // < 0: left alone
                if (fluid && inside(x, level.min, level.max)) want = tait(std::max(0.0, rho0 * g * (lvl - x[2])));
                else if (fluid && inside(x, pressure.min, pressure.max)) want = tait(350.0);
                held += want > 0;
                for (int k = 0; k < 4; ++k) {
                    const std::size_t w = 4 * i + static_cast<std::size_t>(k);
                    const bool ok = want < 0 || k < 3 ? same_bits(v[w], v0[w]) && same_bits(acc[w], a0[w]) && same_bits(sc[w], s0[w])
                                                      : std::abs(v[w] - want) <= 2e-6 * want && acc[w] == 0.0f && sc[w] == 0.0f;
                    if (!ok && bad++ < 8)
                        FAIL_CHECK("particle " << i << " at z = " << x[2] << " component " << k << ": density " << v[w] << " (want "
                                               << want << "), drho " << acc[w] << ", " << sc[w]);
                }
            }
            CHECK(bad == 0);
            CHECK(held > 500);
        }
    }
}

TEST_CASE("outlet zones: the fluid past a zone's face is removed and counted by the cell pass, nothing else") {
    Scene s = zone_scene();
    Outlet up;  // leaves by its x+ face at x = 0.25
    up.zone = true;
    up.axis = 0;
    up.upper = true;
    up.min = {0.15, 0.0, -0.05};
    up.max = {0.25, 0.1, 0.1};
    Outlet down;  // leaves by its z- face at z = -0.02, across y in [0.1, 0.17)
    down.zone = true;
    down.axis = 2;
    down.upper = false;
    down.min = {-0.04, 0.1, -0.02};
    down.max = {0.3, 0.17, 0.05};
    down.level = 0.03;
    s.outlets = {up, down};
    s.validate();
    auto gen = test::rng(3403);
    const Particles p = random_particles(gen, s, 8000);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support());
        ParticleStore ps(*d, grid, p.size());
        ps.upload(p);
        std::vector<float> before(4 * p.size());
        d->read(ps.pos, before.data(), before.size());
        OutletZones zones(*d, grid, s);
        zones.remove_past(ps);
        std::vector<float> after(4 * p.size());
        d->read(ps.pos, after.data(), after.size());
        std::size_t bad = 0, want_removed = 0, marked = 0, ambiguous = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Vec3& x = p.position[i];
            const bool fluid = p.type[i] == ParticleType::fluid;
            auto past = [&](const Outlet& o) {
                const int a = (o.axis + 1) % 3, b = (o.axis + 2) % 3;
                const bool across = x[a] >= o.min[a] && x[a] < o.max[a] && x[b] >= o.min[b] && x[b] < o.max[b];
                return across && (o.upper ? x[o.axis] >= o.max[o.axis] : x[o.axis] < o.min[o.axis]);
            };
            const bool gone = fluid && (past(up) || past(down));
            const bool changed = std::memcmp(&before[4 * i], &after[4 * i], 4 * sizeof(float)) != 0;
            if (near_faces(x, up.min, up.max, 1e-5) || near_faces(x, down.min, down.max, 1e-5)) {
                ambiguous += 1;
                marked += changed;
                continue;
            }
            want_removed += gone;
            marked += changed;
            if (gone != changed && bad++ < 8)
                FAIL_CHECK("particle " << i << " at (" << x[0] << ", " << x[1] << ", " << x[2] << "), fluid " << fluid << ": past a face "
                                       << gone << ", marked " << changed);
        }
        CHECK(bad == 0);
        CHECK(want_removed > 300);
        CellPipeline cells(*d, grid);
        const auto pass = cells.run(ps);
        CHECK(pass.removed == marked);  // every marked particle, counted as one that left the domain
        CHECK(ps.ranges.owned == p.size() - marked);
        MESSAGE(d->label() << ": " << want_removed << " past a face (" << ambiguous << " near a face not compared)");
    }
}
}
