// The force pass against a CPU implementation of the same formulas (kernels/forces.cl), every
// device, every interaction form, each diffusion variant, artificial viscosity on and off and
// laminar viscosity, both kernels; the clusters form bitwise the fine form (the same terms summed
// in the same order).
#include "device/physics.hpp"
#include "multi/list_schedule.hpp"
#include "support/sph_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>

using namespace clsph;
using namespace clsph::device;

namespace {



struct Expect {
    std::vector<std::array<double, 4>> value;  // acceleration xyz + drho/dt (or density)
    std::vector<double> scale;                 // sum of |terms|: the size round-off is relative to
};

// CPU sps.cl in double: per particle tau / rho^2 as (xx, xy, xz, yy, yz, zz); 0 for boundary particles.
std::vector<std::array<double, 6>> cpu_sps(const Scene& s, const Particles& p) {
    const auto& ph = s.physics;
    const double h = ph.h(), m = ph.rho0 * ph.dp * ph.dp * ph.dp;
    const double smag = 0.12 * ph.dp * 0.12 * ph.dp, blin = 2.0 / 3.0 * 0.0066 * ph.dp * ph.dp;
    std::vector<std::array<double, 6>> tau(p.size(), {0, 0, 0, 0, 0, 0});
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::fluid) continue;
        double g[3][3] = {};  // g[a][b] = d v_a / d x_b
        for (std::size_t j = 0; j < p.size(); ++j) {
            double d[3], r2 = 0;
            for (int k = 0; k < 3; ++k) {
                d[k] = p.position[i][k] - p.position[j][k];
                r2 += d[k] * d[k];
            }
            if (i == j || r2 >= 4 * h * h) continue;
            const double f = test::reference_f(ph.kernel, h, std::sqrt(r2)), vol = m / p.density[j];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    g[a][b] += vol * (double(p.velocity[j][a]) - p.velocity[i][a]) * f * d[b];
        }
        const double xy = g[0][1] + g[1][0], xz = g[0][2] + g[2][0], yz = g[1][2] + g[2][1];
        const double s2 = 2 * (g[0][0] * g[0][0] + g[1][1] * g[1][1] + g[2][2] * g[2][2]) + xy * xy + xz * xz + yz * yz;
        const double nu_t = smag * std::sqrt(s2), div = g[0][0] + g[1][1] + g[2][2];
        const double iso = -(2.0 / 3.0 * nu_t * div + blin * s2), rho = p.density[i];
        tau[i] = {(2 * nu_t * g[0][0] + iso) / rho, nu_t * xy / rho, nu_t * xz / rho,
                  (2 * nu_t * g[1][1] + iso) / rho, nu_t * yz / rho, (2 * nu_t * g[2][2] + iso) / rho};
    }
    return tau;
}

// CPU forces.cl: every term written out separately, in double.
Expect cpu_forces(const Scene& s, const Particles& p) {
    const auto& ph = s.physics;
    const double h = ph.h(), c0 = s.sound_speed(), rho0 = ph.rho0;
    const double B = c0 * c0 * rho0 / 7.0, m = rho0 * ph.dp * ph.dp * ph.dp;
    const double eta2 = 0.01 * h * h, dcoef = ph.delta * h * c0, hydro = rho0 * rho0 / (7.0 * B);
    auto pres = [&](double rho) { return B * (std::pow(rho / rho0, 7.0) - 1); };
    const bool mdbc = s.boundary_method == BoundaryMethod::mdbc;
    const std::size_t n = p.size();
    const bool sps = ph.viscosity == Viscosity::laminar_sps;
    const auto tau = sps ? cpu_sps(s, p) : std::vector<std::array<double, 6>>(n, {0, 0, 0, 0, 0, 0});
    Expect e;
    e.value.assign(n, {0, 0, 0, 0});
    e.scale.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const bool fi = p.type[i] == ParticleType::fluid;
        const double ri = p.density[i], pi = pres(ri);
        double ax = 0, ay = 0, az = 0, drho = 0, scale = 0;
        for (std::size_t j = 0; j < n; ++j) {
            if (i == j) continue;
            double d[3], v[3], r2 = 0, vd = 0;
            for (int k = 0; k < 3; ++k) {
                d[k] = p.position[i][k] - p.position[j][k];
                v[k] = double(p.velocity[i][k]) - p.velocity[j][k];
                r2 += d[k] * d[k];
                vd += v[k] * d[k];
            }
            if (r2 >= 4 * h * h) continue;
            const double r = std::sqrt(r2), f = test::reference_f(ph.kernel, h, r), rj = p.density[j];
            const bool fj = p.type[j] == ParticleType::fluid;
            // continuity
            const double cont = m * vd * f;
            if (!(ph.density == DensityMode::summation && fi)) drho += cont;
            scale += std::abs(cont);
            // diffusion
            if (ph.diffusion == Diffusion::molteni_colagrossi) {
                const double t = dcoef * 2 * (rj - ri) * (-f) * m / rj;
                drho += t;
                scale += std::abs(t);
            } else if (ph.diffusion == Diffusion::fourtakas && fi && fj) {
                const double gr = ph.gravity[0] * -d[0] + ph.gravity[1] * -d[1] + ph.gravity[2] * -d[2];
                const double t = dcoef * 2 * (rj - ri - hydro * gr) * (-f) * m / rj;
                drho += t;
                scale += std::abs(t);
            }
            if (fi) {
                double coef = (pi + pres(rj)) / (ri * rj);                        // pressure
                if (vd < 0 && ph.viscosity == Viscosity::artificial)  // alpha between fluid, alpha_wall with boundary
                    coef += -(fj ? ph.alpha : ph.alpha_wall) * c0 * (h * vd / (r2 + eta2)) / (0.5 * (ri + rj));
                ax += -m * coef * f * d[0];
                ay += -m * coef * f * d[1];
                az += -m * coef * f * d[2];
                scale += std::abs(m * coef * f) * r;
                if (ph.viscosity != Viscosity::artificial) {  // Morris (laminar): fluid and boundary neighbours alike
                    const double lam = m * 4 * ph.kinematic_viscosity * f * r2 / ((ri + rj) * (r2 + eta2));
                    ax += lam * v[0];
                    ay += lam * v[1];
                    az += lam * v[2];
                    scale += std::abs(lam) * (std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]));
                }
                if (sps) {  // m (tau_i + tau_j) . grad W, grad W = F d
                    const auto& a = tau[i];
                    const auto& b = tau[j];
                    const double t[3][3] = {{a[0] + b[0], a[1] + b[1], a[2] + b[2]},
                                            {a[1] + b[1], a[3] + b[3], a[4] + b[4]},
                                            {a[2] + b[2], a[4] + b[4], a[5] + b[5]}};
                    double add[3] = {0, 0, 0};
                    for (int k = 0; k < 3; ++k)
                        for (int l = 0; l < 3; ++l) {
                            add[k] += m * t[k][l] * f * d[l];
                            scale += std::abs(m * t[k][l] * f * d[l]);
                        }
                    ax += add[0];
                    ay += add[1];
                    az += add[2];
                }
            }
        }
        if (!fi && mdbc) drho = 0;  // mDBC: boundary densities come from ghost nodes, not continuity
        if (fi) {
            ax += ph.gravity[0];
            ay += ph.gravity[1];
            az += ph.gravity[2];
        }
        e.value[i] = {ax, ay, az, drho};
        e.scale[i] = scale + 1e-3;
    }
    return e;
}

// Shepard-free summation density with the free-surface floor of density.cl.
std::vector<double> cpu_summation(const Scene& s, const Particles& p) {
    const auto& ph = s.physics;
    const double h = ph.h(), m = ph.rho0 * ph.dp * ph.dp * ph.dp;
    std::vector<double> out(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        double mw = 0, vw = 0;
        for (std::size_t j = 0; j < p.size(); ++j) {
            double r2 = 0;
            for (int k = 0; k < 3; ++k) r2 += (p.position[i][k] - p.position[j][k]) * (p.position[i][k] - p.position[j][k]);
            const double w = test::reference_w(ph.kernel, h, std::sqrt(r2));
            mw += m * w;
            vw += m / p.density[j] * w;
        }
        out[i] = p.type[i] != ParticleType::fluid ? p.density[i] : (vw < 0.95 ? std::max(mw, ph.rho0) : mw);
    }
    return out;
}

Particles random_block(std::mt19937_64& gen, double dp) {
    std::uniform_real_distribution<double> jitter(-0.3 * dp, 0.3 * dp), vel(-1.0, 1.0), rho(980.0, 1020.0);
    Particles p;
    std::uint32_t id = 0;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 7; ++k) {
                const bool wall = k < 2;  // two bottom layers are boundary particles
                const Vec3 x{0.1 + i * dp + (wall ? 0 : jitter(gen)), 0.1 + j * dp + (wall ? 0 : jitter(gen)),
                             0.1 + k * dp + (wall ? 0 : jitter(gen))};
                const std::array<float, 3> v = wall ? std::array<float, 3>{0, 0, 0}
                                                    : std::array<float, 3>{float(vel(gen)), float(vel(gen)), float(vel(gen))};
                p.push_back(id++, wall ? ParticleType::boundary : ParticleType::fluid, x, v, float(rho(gen)), 0.0f);
            }
    return p;
}

}  // namespace

TEST_SUITE("physics") {
TEST_CASE("every interaction term matches a CPU implementation on every device") {
    struct Config {
        Diffusion diffusion;
        double alpha;
        KernelType kernel;
        DensityMode density;
        double hdp;  // 1.5: cells of 27 lattice sites; 2.2: of ~85, so cells take several 32-particle chunks
        int reach;   // the grid's reach (1: cells of a support; 2: half a support along a and b)
        bool mdbc;   // boundaries.method mdbc (boundary particles get no drho/dt)
        Viscosity viscosity = Viscosity::artificial;
    };
    const Config configs[] = {{Diffusion::none, 0.0, KernelType::wendland_c2, DensityMode::continuity, 1.5, 1, false},
                              {Diffusion::molteni_colagrossi, 0.5, KernelType::cubic_spline, DensityMode::continuity, 1.5, 1, false},
                              {Diffusion::fourtakas, 0.5, KernelType::wendland_c2, DensityMode::continuity, 1.5, 1, false},
                              {Diffusion::fourtakas, 0.02, KernelType::wendland_c2, DensityMode::summation, 1.5, 1, false},
                              {Diffusion::fourtakas, 0.1, KernelType::wendland_c2, DensityMode::continuity, 2.2, 1, false},
                              {Diffusion::fourtakas, 0.1, KernelType::wendland_c2, DensityMode::summation, 2.2, 1, false},
                              {Diffusion::fourtakas, 0.5, KernelType::cubic_spline, DensityMode::continuity, 2.2, 2, false},
                              {Diffusion::fourtakas, 0.1, KernelType::wendland_c2, DensityMode::continuity, 2.2, 2, true},
                              {Diffusion::molteni_colagrossi, 0.1, KernelType::wendland_c2, DensityMode::summation, 1.5, 2, false},
                              {Diffusion::fourtakas, 0.1, KernelType::wendland_c2, DensityMode::continuity, 1.5, 1, false, Viscosity::laminar},
                              {Diffusion::molteni_colagrossi, 0.1, KernelType::cubic_spline, DensityMode::summation, 2.2, 2, false, Viscosity::laminar},
                              {Diffusion::fourtakas, 0.1, KernelType::wendland_c2, DensityMode::continuity, 2.2, 2, true, Viscosity::laminar},
                              {Diffusion::fourtakas, 0.1, KernelType::cubic_spline, DensityMode::summation, 1.5, 1, false, Viscosity::laminar_sps},
                              {Diffusion::molteni_colagrossi, 0.1, KernelType::wendland_c2, DensityMode::continuity, 2.2, 2, true, Viscosity::laminar_sps}};
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        for (const auto& c : configs) {
            std::vector<float> fine_acc, fine_rho;  // the clusters form sums the same terms in the same order
            for (const Interaction form : interaction_forms()) {
                CAPTURE(static_cast<int>(c.diffusion));
                CAPTURE(c.alpha);
                CAPTURE(c.hdp);
                CAPTURE(c.reach);
                CAPTURE(std::string(interaction_name(form)));
                CAPTURE(static_cast<int>(c.density));
                Scene s;
                s.physics.dp = 0.01;
                s.physics.hdp = c.hdp;
                s.physics.c0 = 15.0;
                s.physics.diffusion = c.diffusion;
                s.physics.alpha = c.alpha;
                s.physics.alpha_wall = 0.5 * c.alpha;
                s.boundary_method = c.mdbc ? BoundaryMethod::mdbc : BoundaryMethod::dbc;
                s.physics.viscosity = c.viscosity;
                s.physics.kinematic_viscosity = 0.02;  // the laminar term as large as the pressure term here
                CAPTURE(static_cast<int>(c.viscosity));
                CAPTURE(c.mdbc);
                s.physics.kernel = c.kernel;
                s.physics.density = c.density;
                s.domain.min = {0, 0, 0};
                s.domain.max = {0.3, 0.3, 0.3};
                auto gen = test::rng(300);
                const Particles in = random_block(gen, s.physics.dp);
                Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support(), -1, {false, false, false}, c.reach);
                ParticleStore ps(*d, grid, in.size());
                ps.upload(in);
                CellPipeline cells(*d, grid);
                Physics phys(*d, grid, s, form);
                cells.run(ps);
                const Particles before = ps.download();  // sorted order, float-rounded values
                d->fill(ps.accel, std::numeric_limits<float>::quiet_NaN(), 4 * ps.capacity());  // poison
                phys.forces(ps, cells, ps.accel);
                std::vector<float> acc(4 * before.size());
                d->read(ps.accel, acc.data(), acc.size());
                const Particles after = ps.download();
                Particles ref_state = before;
                if (c.density == DensityMode::summation) {
                    const auto rho = cpu_summation(s, before);
                    for (std::size_t i = 0; i < rho.size(); ++i) {
                        CHECK(after.density[i] == doctest::Approx(rho[i]).epsilon(1e-5));
                        ref_state.density[i] = after.density[i];
                    }
                }
                const Expect e = cpu_forces(s, ref_state);
                std::size_t bad = 0;
                for (std::size_t i = 0; i < before.size(); ++i)
                    for (int k = 0; k < 4; ++k) {
                        const double got = acc[4 * i + k], want = e.value[i][k];
                        if (!(std::abs(got - want) <= 2e-5 * e.scale[i] + 1e-6) && bad++ < 8)
                            FAIL_CHECK("particle " << before.id[i] << " component " << k << ": device " << got
                                                   << ", CPU " << want << " (scale " << e.scale[i] << ")");
                    }
                CHECK(bad == 0);
                std::vector<float> rho(after.density.begin(), after.density.end());
                if (form == Interaction::fine) {
                    fine_acc = acc;
                    fine_rho = rho;
                } else if (form == Interaction::clusters) {
                    REQUIRE(fine_acc.size() == acc.size());
                    CHECK(std::memcmp(fine_acc.data(), acc.data(), acc.size() * sizeof(float)) == 0);
                    CHECK(std::memcmp(fine_rho.data(), rho.data(), rho.size() * sizeof(float)) == 0);
                }
            }
        }
    }
}
TEST_CASE("tables and cluster lists kept over steps (run.list_buffer): the CPU's forces while no particle moved half the buffer; a longer move is caught") {
    // Cells the buffer wider; the particles moved in place (their offsets from the cells they were
    // sorted into) three times by up to 0.3 of half the buffer, each pass on the first tables and
    // lists against the double-precision reference at the new positions. Then one particle moves
    // two supports: the schedule asks for a build, the stale tables miss its new neighbours (the
    // check fails there: the negative control), and the rebuilt ones find them again.
    struct Config { double hdp; int reach; };
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        for (const Config c : {Config{1.5, 1}, Config{2.2, 2}})
            for (const Interaction form : interaction_forms()) {
                CAPTURE(c.hdp);
                CAPTURE(std::string(interaction_name(form)));
                Scene s;
                s.physics.dp = 0.01;
                s.physics.hdp = c.hdp;
                s.physics.c0 = 15.0;
                s.physics.diffusion = Diffusion::fourtakas;
                s.physics.alpha = 0.1;
                s.physics.alpha_wall = 0.05;
                s.domain.min = {0, 0, 0};
                s.domain.max = {0.3, 0.3, 0.3};
                s.run.list_buffer = 0.25;
                const double support = s.physics.support(), half = 0.5 * s.run.list_buffer * support;
                auto gen = test::rng(331);
                const Particles in = random_block(gen, s.physics.dp);
                Grid grid(Box{s.domain.min, s.domain.max}, support * (1 + s.run.list_buffer), -1, {false, false, false},
                          c.reach);
                ParticleStore ps(*d, grid, in.size());
                ps.upload(in);
                CellPipeline cells(*d, grid);
                Physics phys(*d, grid, s, form);
                multi::ListSchedule lists(half);
                cells.run(ps);
                lists.built();
                const std::size_t n = in.size();
                // One force pass on the tables as they are; the components off the reference.
                auto pass = [&](bool kept) {
                    phys.keep_tables(kept);
                    const Particles state = ps.download();
                    d->fill(ps.accel, std::numeric_limits<float>::quiet_NaN(), 4 * ps.capacity());  // poison
                    phys.forces(ps, cells, ps.accel);
                    std::vector<float> acc(4 * n);
                    d->read(ps.accel, acc.data(), acc.size());
                    const Expect e = cpu_forces(s, state);
                    std::size_t bad = 0;
                    for (std::size_t i = 0; i < n; ++i)
                        for (int k = 0; k < 4; ++k)
                            bad += !(std::abs(acc[4 * i + k] - e.value[i][k]) <= 2e-5 * e.scale[i] + 1e-6);
                    return bad;
                };
                // Particle i's offset moved by dx (the key in w, its cell, stays).
                auto move = [&](const std::vector<std::array<double, 3>>& dx) {
                    std::vector<float> pos(4 * n);
                    d->read(ps.pos, pos.data(), pos.size());
                    for (std::size_t i = 0; i < n; ++i)
                        for (int k = 0; k < 3; ++k) pos[4 * i + k] += static_cast<float>(dx[i][k]);
                    d->write(ps.pos, pos.data(), pos.size());
                };
                CHECK(pass(false) == 0);
                const double step = 0.3 * half;
                std::uniform_real_distribution<double> u(-1.0, 1.0);
                const Particles sorted = ps.download();
                for (int k = 0; k < 3; ++k) {
                    REQUIRE(!lists.due(1.0, step * step, 0.0));
                    std::vector<std::array<double, 3>> dx(n, {0, 0, 0});
                    for (std::size_t i = 0; i < n; ++i) {
                        if (sorted.type[i] != ParticleType::fluid) continue;
                        std::array<double, 3> v{u(gen), u(gen), u(gen)};
                        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                        for (auto& x : v) x *= step / std::max(len, 1.0);  // |dx| <= step
                        dx[i] = v;
                    }
                    move(dx);
                    lists.kept(1.0, step * step, 0.0);
                    CHECK(pass(true) == 0);
                }
                CHECK(lists.age() == 3);
                // The fluid particle nearest the block's -x face, mid-block, two supports along +x.
                std::size_t far = n;
                for (std::size_t i = 0; i < n; ++i)
                    if (sorted.type[i] == ParticleType::fluid && std::abs(sorted.position[i][1] - 0.135) < 0.01 &&
                        (far == n || sorted.position[i][0] < sorted.position[far][0]))
                        far = i;
                REQUIRE(far < n);
                std::vector<std::array<double, 3>> dx(n, {0, 0, 0});
                dx[far][0] = 2 * support;
                move(dx);
                CHECK(lists.due(1.0, 4 * support * support, 0.0));
                CHECK(pass(true) > 0);  // stale tables: the moved particle's new neighbours missed
                cells.run(ps);
                lists.built();
                CHECK(pass(false) == 0);
            }
    }
}

TEST_CASE("laminar+sps: the stress and its force as plain C++ has them, on every device and form") {
    // Densities at rho0 (no pressure) and nu = 0 (no laminar term): the accelerations are the SPS
    // stress's alone, each particle's tau / rho^2 read back too; velocities of 10 m/s over dp =
    // 0.01 m make the eddy viscosity (0.12 dp)^2 |S| some 1e-3 m^2/s.
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        for (const Interaction form : interaction_forms()) {
            CAPTURE(std::string(interaction_name(form)));
            Scene s;
            s.physics.dp = 0.01;
            s.physics.hdp = 1.5;
            s.physics.c0 = 15.0;
            s.physics.gravity = {0, 0, 0};
            s.physics.viscosity = Viscosity::laminar_sps;
            s.physics.kinematic_viscosity = 0;
            s.domain.min = {0, 0, 0};
            s.domain.max = {0.3, 0.3, 0.3};
            auto gen = test::rng(3400);
            Particles in = random_block(gen, s.physics.dp);
            for (std::size_t i = 0; i < in.size(); ++i) {
                in.density[i] = static_cast<float>(s.physics.rho0);
                for (auto& v : in.velocity[i]) v *= 10.0f;
            }
            Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support(), -1, {false, false, false}, 1);
            ParticleStore ps(*d, grid, in.size());
            ps.upload(in);
            CellPipeline cells(*d, grid);
            Physics phys(*d, grid, s, form);
            cells.run(ps);
            const Particles before = ps.download();
            d->fill(ps.accel, std::numeric_limits<float>::quiet_NaN(), 4 * ps.capacity());  // poison
            phys.forces(ps, cells, ps.accel);
            const std::size_t n = before.size();
            std::vector<float> acc(4 * n), tau(8 * n);
            d->read(ps.accel, acc.data(), acc.size());
            d->read(phys.tau(), tau.data(), tau.size());
            const auto want_tau = cpu_sps(s, before);
            const Expect e = cpu_forces(s, before);
            std::size_t bad = 0;
            double largest = 0;
            for (std::size_t i = 0; i < n; ++i) {
                double tscale = 1e-12;
                for (int k = 0; k < 6; ++k) tscale = std::max(tscale, std::abs(want_tau[i][k]));
                const float got_tau[6] = {tau[8 * i], tau[8 * i + 1], tau[8 * i + 2], tau[8 * i + 3], tau[8 * i + 4], tau[8 * i + 5]};
                for (int k = 0; k < 6; ++k)
                    if (!(std::abs(got_tau[k] - want_tau[i][k]) <= 1e-4 * tscale + 1e-12) && bad++ < 8)
                        FAIL_CHECK("particle " << before.id[i] << " tau " << k << ": device " << got_tau[k] << ", CPU "
                                               << want_tau[i][k]);
                for (int k = 0; k < 3; ++k) {
                    const double got = acc[4 * i + k], want = e.value[i][k];
                    largest = std::max(largest, std::abs(want));
                    if (!(std::abs(got - want) <= 2e-5 * e.scale[i] + 1e-6) && bad++ < 8)
                        FAIL_CHECK("particle " << before.id[i] << " component " << k << ": device " << got << ", CPU "
                                               << want << " (scale " << e.scale[i] << ")");
                }
            }
            CHECK(bad == 0);
            CHECK(largest > 1.0);  // the stress does push: m/s^2
        }
    }
}
}
