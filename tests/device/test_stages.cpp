// The stages that used to be checked only end to end, each against plain C++ on random inputs
// (seed printed), on every device, at sizes 0, 1, 2, odd and large, with what a kernel must not
// write poisoned: kick_drift, kick (its reductions and the bad-value check), commit_density and
// the exchange's settle / flag / gather of key ranges (the probes: test_stages_probes.cpp).
#include "cl/kernel_args.hpp"
#include "device/cell_pipeline.hpp"
#include "device/physics.hpp"
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

namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;

float poison_float() {
    float f;
    std::memcpy(&f, &kPoison, sizeof f);
    return f;
}
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool close(double got, double want, double rel = 2e-6, double abs = 1e-12) {
    return std::abs(got - want) <= rel * std::abs(want) + abs;
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
