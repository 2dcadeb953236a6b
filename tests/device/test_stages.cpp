// The stages that used to be checked only end to end, each against plain C++ on random inputs
// (seed printed), on every device, at sizes 0, 1, 2, odd and large, with what a kernel must not
// write poisoned: kick_drift, kick (its reductions and the bad-value check), commit_density,
// probes, and the exchange's settle / flag / gather of key ranges.
#include "cl/kernel_args.hpp"
#include "device/cell_pipeline.hpp"
#include "device/physics.hpp"
#include "probes/gauges.hpp"
#include "support/scenes.hpp"
#include "support/sph_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace clsph;
using namespace clsph::device;

namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;
const std::size_t kSizes[] = {0, 1, 2, 37, 4099};

float poison_float() {
    float f;
    std::memcpy(&f, &kPoison, sizeof f);
    return f;
}
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool close(double got, double want, double rel = 2e-6, double abs = 1e-12) {
    return std::abs(got - want) <= rel * std::abs(want) + abs;
}

Scene box_scene(double dp) {
    Scene s;
    s.physics.dp = dp;
    s.physics.c0 = 20.0;
    s.domain.min = {0, 0, 0};
    s.domain.max = {1, 0.5, 0.5};
    return s;
}

// Raw device arrays for a store of n particles: [ghosts | owned | ghosts] with `g` ghosts each side.
struct Raw {
    std::vector<float> pos, velrho, accel, scratch;
    std::vector<std::uint32_t> id;
};

Raw random_raw(std::mt19937_64& gen, std::size_t n, float cell) {
    std::uniform_real_distribution<float> off(-0.5f * cell, 0.5f * cell), v(-2.0f, 2.0f), a(-30.0f, 30.0f),
        rho(990.0f, 1010.0f), drho(-50.0f, 50.0f);
    std::uniform_int_distribution<std::uint32_t> key(0, 1000);
    Raw r;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t k = key(gen);
        float kf;
        std::memcpy(&kf, &k, sizeof kf);
        r.pos.insert(r.pos.end(), {off(gen), off(gen), off(gen), kf});
        r.velrho.insert(r.velrho.end(), {v(gen), v(gen), v(gen), rho(gen)});
        r.accel.insert(r.accel.end(), {a(gen), a(gen), a(gen), drho(gen)});
        r.scratch.insert(r.scratch.end(), {a(gen), a(gen), a(gen), drho(gen)});
        const bool fluid = gen() % 4 != 0;
        r.id.push_back(static_cast<std::uint32_t>(i) | ((fluid ? CLSPH_TYPE_FLUID : CLSPH_TYPE_BOUNDARY) << CLSPH_TYPE_SHIFT));
    }
    return r;
}

void write_raw(cl_rt::Device& d, ParticleStore& ps, const Raw& r) {
    const std::size_t n = r.id.size();
    ps.reserve(n);
    d.write(ps.pos, r.pos.data(), 4 * n);
    d.write(ps.velrho, r.velrho.data(), 4 * n);
    d.write(ps.accel, r.accel.data(), 4 * n);
    d.write(ps.scratch, r.scratch.data(), 4 * n);
    d.write(ps.id, r.id.data(), n);
}

std::vector<float> read4(cl_rt::Device& d, const cl_rt::Buffer& b, std::size_t n) {
    std::vector<float> out(4 * n);
    d.read(b, out.data(), 4 * n);
    return out;
}

bool is_fluid(std::uint32_t id) { return (id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID; }

}  // namespace

TEST_SUITE("stages") {
TEST_CASE("kick_drift: positions and predicted velocity and density of the owned particles only") {
    const Scene scene = box_scene(0.02);
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(501);
        Physics phys(*d, grid, scene);
        const float rho0 = phys.params().rho0;
        for (std::size_t owned : kSizes) {
            CAPTURE(owned);
            const std::size_t g = 3, n = g + owned + g;
            const float dt = std::uniform_real_distribution<float>(1e-5f, 1e-3f)(gen);
            const Raw r = random_raw(gen, n, static_cast<float>(grid.params().cell_s));
            ParticleStore ps(*d, grid, n);
            write_raw(*d, ps, r);
            ps.ranges = ParticleRanges{g, owned, g};
            phys.kick_drift(ps, dt);
            const auto pos = read4(*d, ps.pos, n), vr = read4(*d, ps.velrho, n), acc = read4(*d, ps.accel, n);
            std::size_t wrong = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const bool mine = i >= g && i < g + owned;
                for (int k = 0; k < 4; ++k) {
                    float want_p = r.pos[4 * i + k], want_v = r.velrho[4 * i + k];
                    if (mine && is_fluid(r.id[i]) && k < 3) {
                        want_p += (r.velrho[4 * i + k] + r.accel[4 * i + k] * (0.5f * dt)) * dt;
                        want_v += r.accel[4 * i + k] * dt;
                    } else if (mine && k == 3) {
                        want_v += r.accel[4 * i + 3] * dt;
                        if (!is_fluid(r.id[i])) want_v = std::max(want_v, rho0);
                    }
                    const bool ok_p = mine && k < 3 ? close(pos[4 * i + k], want_p, 1e-6, 1e-9) : same_bits(pos[4 * i + k], want_p);
                    const bool ok_v = mine ? close(vr[4 * i + k], want_v, 1e-6, 1e-9) : same_bits(vr[4 * i + k], want_v);
                    wrong += !ok_p + !ok_v + !same_bits(acc[4 * i + k], r.accel[4 * i + k]);
                }
            }
            CHECK(wrong == 0);
        }
    }
}

TEST_CASE("symplectic predict and correct: half and full steps of the owned particles only") {
    Scene scene = box_scene(0.02);
    scene.physics.integrator = Integrator::symplectic;
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(507);
        Physics phys(*d, grid, scene);
        REQUIRE(phys.symplectic());
        const double rho0 = phys.params().rho0;
        for (std::size_t owned : kSizes) {
            CAPTURE(owned);
            const std::size_t g = 3, n = g + owned + g;
            const float dt = std::uniform_real_distribution<float>(1e-5f, 1e-3f)(gen);
            const Raw r = random_raw(gen, n, static_cast<float>(grid.params().cell_s));
            ParticleStore ps(*d, grid, n);
            write_raw(*d, ps, r);
            ps.ranges = ParticleRanges{g, owned, g};
            // The predictor, then the corrector with the half step's accelerations in scratch.
            phys.predict(ps, dt);
            const auto pos_h = read4(*d, ps.pos, n), vr_h = read4(*d, ps.velrho, n);
            phys.correct(ps, ps.scratch, dt);
            const auto pos = read4(*d, ps.pos, n), vr = read4(*d, ps.velrho, n), acc = read4(*d, ps.accel, n);
            std::size_t wrong = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const bool mine = i >= g && i < g + owned, fluid = is_fluid(r.id[i]);
                const double hdt = 0.5 * dt;
                // In double from the inputs: the half step, then the full one.
                double xh[3], vh[3], x1[3], v1[3], a0[4], AH[4];
                for (int k = 0; k < 4; ++k) a0[k] = r.accel[4 * i + k], AH[k] = r.scratch[4 * i + k];
                double rho_h = r.velrho[4 * i + 3], rho1;
                for (int k = 0; k < 3; ++k) {
                    xh[k] = r.pos[4 * i + k] + (mine && fluid ? r.velrho[4 * i + k] * hdt : 0.0);
                    vh[k] = r.velrho[4 * i + k] + (mine && fluid ? a0[k] * hdt : 0.0);
                }
                if (mine) rho_h = fluid ? rho_h + a0[3] * hdt : std::max(rho_h + a0[3] * hdt, rho0);
                const double rho_n = rho_h - a0[3] * hdt, eps = -(AH[3] / rho_h) * dt;
                rho1 = mine ? rho_n * (2 - eps) / (2 + eps) : rho_h;
                if (mine && !fluid) rho1 = std::max(rho1, rho0);
                for (int k = 0; k < 3; ++k) {
                    v1[k] = mine && fluid ? vh[k] - a0[k] * hdt + AH[k] * dt : vh[k];
                    x1[k] = mine && fluid ? xh[k] + v1[k] * hdt : xh[k];
                }
                for (int k = 0; k < 4; ++k) {
                    const double want_ph = k < 3 ? xh[k] : r.pos[4 * i + 3], want_vh = k < 3 ? vh[k] : rho_h;
                    const double want_p = k < 3 ? x1[k] : r.pos[4 * i + 3], want_v = k < 3 ? v1[k] : rho1;
                    if (mine) {
                        wrong += !(k < 3 ? close(pos_h[4 * i + k], want_ph, 1e-6, 1e-9) : same_bits(pos_h[4 * i + k], r.pos[4 * i + k]));
                        wrong += !close(vr_h[4 * i + k], want_vh, 1e-6, 1e-6);
                        wrong += !(k < 3 ? close(pos[4 * i + k], want_p, 1e-6, 1e-9) : same_bits(pos[4 * i + k], r.pos[4 * i + k]));
                        wrong += !close(vr[4 * i + k], want_v, 1e-5, 1e-5);
                    } else {  // ghosts: untouched, bit for bit
                        wrong += !same_bits(pos[4 * i + k], r.pos[4 * i + k]) + !same_bits(vr[4 * i + k], r.velrho[4 * i + k]);
                    }
                    wrong += !same_bits(acc[4 * i + k], r.accel[4 * i + k]);  // a_n stays for the next step's kick
                }
            }
            CHECK(wrong == 0);
        }
    }
}

TEST_CASE("kick: second half-kick, its reductions and the lowest bad index") {
    const Scene scene = box_scene(0.02);
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(502);
        Physics phys(*d, grid, scene);
        const SphParams sp = phys.params();
        for (std::size_t owned : kSizes)
            for (int bad_case = 0; bad_case < 3; ++bad_case) {  // none, a NaN, a density out of band
                CAPTURE(owned);
                CAPTURE(bad_case);
                const std::size_t g = 2, n = g + owned + g;
                const float dt = std::uniform_real_distribution<float>(1e-5f, 1e-3f)(gen);
                Raw r = random_raw(gen, n, static_cast<float>(grid.params().cell_s));
                // Bad values in the ghosts never count; in the owned range the lowest index does.
                r.velrho[4 * 0 + 3] = std::numeric_limits<float>::quiet_NaN();
                std::int64_t want_bad = -1;
                if (bad_case > 0 && owned > 0) {
                    std::uniform_int_distribution<std::size_t> at(g, g + owned - 1);
                    const std::size_t i1 = at(gen), i2 = at(gen);
                    if (bad_case == 1) r.scratch[4 * i1 + 1] = std::numeric_limits<float>::quiet_NaN();
                    if (bad_case == 2) r.velrho[4 * i1 + 3] = 0.5f * sp.rho_min;
                    r.velrho[4 * i2 + 3] = 2.0f * sp.rho_max;
                    for (std::size_t i : {i1, i2}) r.id[i] = (r.id[i] & CLSPH_ID_MASK) | (CLSPH_TYPE_FLUID << CLSPH_TYPE_SHIFT);
                    want_bad = static_cast<std::int64_t>(std::min(i1, i2));
                }
                ParticleStore ps(*d, grid, n);
                write_raw(*d, ps, r);
                ps.ranges = ParticleRanges{g, owned, g};
                cl_rt::EventSet done;
                phys.enqueue_kick(ps, dt, done);
                done.wait("the test kick");
                const KickResult k = phys.kick_result();
                const auto vr = read4(*d, ps.velrho, n), acc = read4(*d, ps.accel, n);
                double v2max = 0, a2max = 0, ke = 0;
                std::size_t fluid = 0, wrong = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    const bool mine = i >= g && i < g + owned;
                    float want[4];
                    for (int c = 0; c < 4; ++c) want[c] = r.velrho[4 * i + c];
                    if (mine) {
                        float da[4];
                        for (int c = 0; c < 4; ++c) da[c] = (r.scratch[4 * i + c] - r.accel[4 * i + c]) * (0.5f * dt);
                        if (is_fluid(r.id[i]))
                            for (int c = 0; c < 4; ++c) want[c] += da[c];
                        else
                            want[3] = std::max(want[3] + da[3], sp.rho0);
                        if (is_fluid(r.id[i])) {
                            const double v2 = double(want[0]) * want[0] + double(want[1]) * want[1] + double(want[2]) * want[2];
                            const double a2 = double(r.scratch[4 * i]) * r.scratch[4 * i] +
                                              double(r.scratch[4 * i + 1]) * r.scratch[4 * i + 1] +
                                              double(r.scratch[4 * i + 2]) * r.scratch[4 * i + 2];
                            if (std::isfinite(v2)) v2max = std::max(v2max, v2);
                            if (std::isfinite(a2)) a2max = std::max(a2max, a2);
                            ke += 0.5 * sp.mass * v2;
                            ++fluid;
                        } else {
                            // A boundary particle's speed bounds the step too (a moving solid's;
                            // kernels/integrate.cl kick): its velocity, which the kick leaves alone.
                            const double v2 = double(want[0]) * want[0] + double(want[1]) * want[1] + double(want[2]) * want[2];
                            if (std::isfinite(v2)) v2max = std::max(v2max, v2);
                        }
                    }
                    for (int c = 0; c < 4; ++c) {
                        const bool ok = mine ? (std::isnan(want[c]) ? std::isnan(vr[4 * i + c]) : close(vr[4 * i + c], want[c], 1e-6, 1e-9))
                                             : same_bits(vr[4 * i + c], want[c]);
                        wrong += !ok;
                        // accel now holds the new accelerations (scratch), everywhere: the buffers traded places.
                        wrong += !same_bits(acc[4 * i + c], r.scratch[4 * i + c]);
                    }
                }
                CHECK(wrong == 0);
                CHECK(k.bad_index == want_bad);
                CHECK(k.fluid == fluid);
                if (bad_case == 0) {
                    CHECK(close(k.max_speed2, v2max, 1e-5));
                    CHECK(close(k.max_accel2, a2max, 1e-5));
                    CHECK(close(k.kinetic_energy, ke, 1e-4, 1e-9));
                }
            }
    }
}

TEST_CASE("commit_density: the new densities into velrho.w of the owned range only") {
    const Scene scene = box_scene(0.02);
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(503);
        auto k = d->kernel("integrate.cl", "commit_density", grid.kernel_options() + " -DWG=" + std::to_string(d->work_group_size(128)));
        for (std::size_t owned : kSizes) {
            CAPTURE(owned);
            const std::size_t g = 5, n = g + owned + g;
            const Raw r = random_raw(gen, n, 0.1f);
            std::vector<float> rho(n);
            for (auto& x : rho) x = std::uniform_real_distribution<float>(900.0f, 1100.0f)(gen);
            auto velrho = d->alloc(4 * n * sizeof(float), "velrho");
            auto rho_b = d->alloc(n * sizeof(float), "rho");
            d->write(velrho, r.velrho.data(), 4 * n);
            d->write(rho_b, rho.data(), n);
            cl_rt::set_args(k, g, g + owned, rho_b, velrho);
            d->launch("test.commit_density", k, owned, 64);
            const auto out = read4(*d, velrho, n);
            std::size_t wrong = 0;
            for (std::size_t i = 0; i < n; ++i)
                for (int c = 0; c < 4; ++c) {
                    const float want = c == 3 && i >= g && i < g + owned ? rho[i] : r.velrho[4 * i + c];
                    wrong += !same_bits(out[4 * i + c], want);
                }
            CHECK(wrong == 0);
        }
    }
}

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

TEST_CASE("settle, flag and gather of key ranges") {
    const Scene scene = box_scene(0.02);
    Grid grid(Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, {false, false, false});
    const GridParams g = grid.params();
    const double cell = g.cell_s;
    auto column_key = [&](std::size_t c) { return c >= g.n_s ? g.invalid_key : static_cast<std::uint32_t>(c) << g.shift_s; };
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(505);
        CellPipeline cells(*d, grid);
        for (std::size_t owned : kSizes) {
            CAPTURE(owned);
            // Owned particles displaced from their cells by up to 2.5 columns along the split axis
            // (some jump more than one, some leave the domain), plus ghosts that must stay as they are.
            std::uniform_real_distribution<double> x(0.0, 1.0), y(0.0, 0.5), shift(-2.5, 2.5);
            const std::size_t ghosts = 4, n = ghosts + owned + ghosts;
            Particles p;
            for (std::size_t i = 0; i < n; ++i)
                p.push_back(static_cast<std::uint32_t>(i), ParticleType::fluid, {x(gen), y(gen), y(gen)}, {0, 0, 0}, 1000.0f, 0.0f);
            ParticleStore ps(*d, grid, n);
            ps.upload(p);
            std::vector<float> pos(4 * n);
            d->read(ps.pos, pos.data(), 4 * n);
            std::vector<std::array<double, 3>> moved(n);
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t key;
                std::memcpy(&key, &pos[4 * i + 3], sizeof key);
                const auto x0 = grid.position(key, {pos[4 * i], pos[4 * i + 1], pos[4 * i + 2]});
                const bool mine = i >= ghosts && i < ghosts + owned;
                // Keep clear of cell faces by a margin, so the host and the device agree on the cell.
                double s = mine ? shift(gen) : 0.0;
                const double frac = s - std::floor(s);
                if (frac < 0.02 || frac > 0.98) s += 0.05;
                pos[4 * i + grid.axis(0)] += static_cast<float>(s * cell);
                moved[i] = x0;
                moved[i][grid.axis(0)] += s * cell;
            }
            d->write(ps.pos, pos.data(), 4 * n);
            ps.ranges = ParticleRanges{ghosts, owned, ghosts};
            const std::size_t lo = g.n_s / 4, hi = g.n_s / 2;
            const KeyRange keep{column_key(lo), column_key(hi)};
            cl_rt::EventSet done;
            cells.enqueue_settle(ps, keep, done);
            done.wait("the test settle");
            const Settled st = cells.settled();
            std::vector<float> after(4 * n);
            d->read(ps.pos, after.data(), 4 * n);
            std::size_t left = 0, jumped = 0, kept = 0, wrong = 0;
            std::vector<std::uint32_t> new_key(n);
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t old_key, key;
                std::memcpy(&old_key, &pos[4 * i + 3], sizeof old_key);
                std::memcpy(&key, &after[4 * i + 3], sizeof key);
                new_key[i] = key;
                const bool mine = i >= ghosts && i < ghosts + owned;
                if (!mine) {
                    wrong += std::memcmp(&pos[4 * i], &after[4 * i], 4 * sizeof(float)) != 0;
                    continue;
                }
                std::array<float, 3> off{};
                bool inside = true;
                for (int k = 0; k < 3; ++k) inside = inside && moved[i][k] >= scene.domain.min[k] && moved[i][k] <= scene.domain.max[k];
                const std::uint32_t want = inside ? grid.locate(moved[i], off) : g.invalid_key;
                wrong += key != want;
                if (want == g.invalid_key) {
                    ++left;
                    continue;
                }
                const auto back = grid.position(key, {after[4 * i], after[4 * i + 1], after[4 * i + 2]});
                for (int k = 0; k < 3; ++k) wrong += std::abs(back[k] - moved[i][k]) > 1e-6;
                const long ds = static_cast<long>(grid.cell_of_key(key)[0]) - static_cast<long>(grid.cell_of_key(old_key)[0]);
                jumped += std::abs(ds) > 1;
                kept += key >= keep.lo && key < keep.hi;
            }
            CHECK(wrong == 0);
            CHECK(st.left_domain == left);
            CHECK(st.jumped == jumped);
            CHECK(st.kept == kept);

            // Gathers: two windows of the settled particles into one outbox, each after a poisoned gap.
            ParticleArrays outbox;
            outbox.allocate(*d, 2 * n + 8, "test outbox");
            d->fill(outbox.pos, kPoison, 4 * (2 * n + 8));
            d->fill(outbox.id, kPoison, 2 * n + 8);
            std::vector<std::uint32_t> ids(n);
            d->read(ps.id, ids.data(), n);
            struct W { std::size_t first, end, base; KeyRange keys; };
            const W windows[2] = {{0, n / 2, 3, keep}, {n / 3, n, 3 + n / 2 + 2, KeyRange{column_key(hi), column_key(g.n_s)}}};
            cells.begin_gathers(2);
            cl_rt::EventSet gathered;
            for (std::size_t b = 0; b < 2; ++b)
                cells.enqueue_gather(ps, windows[b].first, windows[b].end, windows[b].keys, outbox, windows[b].base, b, gathered);
            gathered.wait("the test gathers");
            std::vector<float> out(4 * (2 * n + 8));
            std::vector<std::uint32_t> out_id(2 * n + 8);
            d->read(outbox.pos, out.data(), out.size());
            d->read(outbox.id, out_id.data(), out_id.size());
            std::vector<char> written(2 * n + 8, 0);
            for (std::size_t b = 0; b < 2; ++b) {
                const W& w = windows[b];
                std::size_t m = 0;
                for (std::size_t i = w.first; i < w.end; ++i) {
                    if (new_key[i] < w.keys.lo || new_key[i] >= w.keys.hi) continue;
                    const std::size_t o = w.base + m++;
                    written[o] = 1;
                    wrong += out_id[o] != ids[i] || std::memcmp(&out[4 * o], &after[4 * i], 4 * sizeof(float)) != 0;
                }
                CHECK(cells.gather_count(b) == m);
            }
            for (std::size_t o = 0; o < written.size(); ++o)
                if (!written[o]) wrong += out_id[o] != kPoison || !same_bits(out[4 * o], poison_float());
            CHECK(wrong == 0);
        }
    }
}
}
