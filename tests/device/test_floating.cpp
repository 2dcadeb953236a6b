// Floating bodies (issue 32 item 3; kernels/floating.cl, multi/rigid_bodies.cpp): the fluid's force
// on each body particle against a CPU implementation in double on random particles, on every
// device, outputs poisoned; the fixed-point sums bitwise those of the device's own per-particle
// forces and close to the CPU's; the host's torque from the moment sums against sum (R r0) x F.
#include "device/physics.hpp"
#include "multi/rigid_bodies.hpp"
#include "support/sph_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

using namespace clsph;
using namespace clsph::device;

namespace {

// A jittered block of fluid with random velocities and densities; the two bottom layers a still
// wall; two bodies of boundary particles inside it (a 3 x 3 x 3 cube, body 0, and a 2 x 3 x 2 one,
// body 1) moving with random velocities.
struct Block {
    Particles p;
    std::vector<int> body;          // by id
    std::vector<Vec3> centre{{0, 0, 0}, {0, 0, 0}};
};

Block random_block(std::mt19937_64& gen, double dp) {
    std::uniform_real_distribution<double> jitter(-0.3 * dp, 0.3 * dp), vel(-1.0, 1.0), rho(990.0, 1030.0);
    Block b;
    std::uint32_t id = 0;
    const std::array<float, 3> v0{float(vel(gen)), float(vel(gen)), float(vel(gen))}, v1{float(vel(gen)), 0.0f, float(vel(gen))};
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k) {
                const bool wall = k < 2;
                const int body = (i >= 2 && i < 5 && j >= 2 && j < 5 && k >= 3 && k < 6)   ? 0
                                 : (i >= 6 && i < 8 && j >= 3 && j < 6 && k >= 4 && k < 6) ? 1
                                                                                           : -1;
                const bool still = wall || body >= 0;
                const Vec3 x{0.1 + i * dp + (still ? 0 : jitter(gen)), 0.1 + j * dp + (still ? 0 : jitter(gen)),
                             0.1 + k * dp + (still ? 0 : jitter(gen))};
                std::array<float, 3> v{float(vel(gen)), float(vel(gen)), float(vel(gen))};
                if (wall) v = {0, 0, 0};
                if (body == 0) v = v0;
                if (body == 1) v = v1;
                b.p.push_back(id++, still ? ParticleType::boundary : ParticleType::fluid, x, v, float(rho(gen)), 0.0f);
                b.body.push_back(body);
            }
    for (int c = 0; c < 2; ++c) {
        double n = 0;
        for (std::size_t i = 0; i < b.p.size(); ++i)
            if (b.body[i] == c) {
                for (int k = 0; k < 3; ++k) b.centre[c][k] += b.p.position[i][k];
                n += 1;
            }
        for (int k = 0; k < 3; ++k) b.centre[c][k] /= n;
    }
    return b;
}

// CPU floating.cl in double: per particle of a body, the force of its fluid neighbours, and the
// sum of the absolute terms (the scale of the round-off).
void cpu_forces(const Scene& s, const Particles& p, const std::vector<int>& body_of_id, std::vector<std::array<double, 3>>& f,
                std::vector<double>& scale) {
    const auto& ph = s.physics;
    const double h = ph.h(), c0 = s.sound_speed(), rho0 = ph.rho0;
    const double B = c0 * c0 * rho0 / 7.0, m = rho0 * ph.dp * ph.dp * ph.dp, eta2 = 0.01 * h * h;
    auto pres = [&](double rho) { return B * (std::pow(rho / rho0, 7.0) - 1); };
    f.assign(p.size(), {0, 0, 0});
    scale.assign(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary || body_of_id[p.id[i]] < 0) continue;
        const double ri = p.density[i], pi = pres(ri);
        for (std::size_t j = 0; j < p.size(); ++j) {
            if (p.type[j] != ParticleType::fluid) continue;
            double d[3], r2 = 0, vd = 0;
            for (int k = 0; k < 3; ++k) {
                d[k] = p.position[i][k] - p.position[j][k];
                r2 += d[k] * d[k];
                vd += (double(p.velocity[i][k]) - p.velocity[j][k]) * d[k];
            }
            if (r2 >= 4 * h * h) continue;
            const double r = std::sqrt(r2), fk = test::reference_f(ph.kernel, h, r), rj = p.density[j];
            double coef = (pi + pres(rj)) / (ri * rj);
            const bool laminar = ph.viscosity != Viscosity::artificial;
            if (vd < 0 && !laminar) coef += -ph.alpha_wall * c0 * (h * vd / (r2 + eta2)) / (0.5 * (ri + rj));
            for (int k = 0; k < 3; ++k) f[i][k] += -m * m * coef * fk * d[k];
            scale[i] += std::abs(m * m * coef * fk) * r;
            if (laminar) {  // the reaction of forces.cl's laminar term on the fluid particle
                const double lam = m * m * 4 * ph.kinematic_viscosity * fk * r2 / ((ri + rj) * (r2 + eta2));
                for (int k = 0; k < 3; ++k) {
                    const double vk = double(p.velocity[i][k]) - p.velocity[j][k];
                    f[i][k] += lam * vk;
                    scale[i] += std::abs(lam * vk);
                }
            }
        }
    }
}

std::int64_t fix(float v) { return static_cast<std::int64_t>(std::llrint(static_cast<double>(v) * multi::kBodyFixedScale)); }

}  // namespace

TEST_SUITE("physics") {
TEST_CASE("floating bodies: the fluid's force on each body particle and the fixed-point sums, on every device") {
    Scene s;
    s.physics.dp = 0.01;
    s.physics.hdp = 1.5;
    s.physics.c0 = 15.0;
    s.physics.alpha_wall = 0.3;
    s.domain.min = {0, 0, 0};
    s.domain.max = {0.3, 0.3, 0.3};
    auto gen = test::rng(3200);
    const Block blk = random_block(gen, s.physics.dp);
    FloatingTable table;
    table.bodies = 2;
    table.body_rest.assign(4 * blk.p.size(), 0.0f);
    for (std::size_t i = 0; i < blk.p.size(); ++i) {
        const int b = blk.body[i];
        for (int k = 0; k < 3; ++k)
            table.body_rest[4 * i + k] = b < 0 ? 0.0f : static_cast<float>(blk.p.position[i][k] - blk.centre[b][k]);
        table.body_rest[4 * i + 3] = static_cast<float>(b);
    }
    for (const Viscosity model : {Viscosity::artificial, Viscosity::laminar})
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        CAPTURE(static_cast<int>(model));
        s.physics.viscosity = model;
        s.physics.kinematic_viscosity = 0.02;  // the laminar term as large as the pressure term here
        Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support(), -1, {false, false, false}, 2);
        ParticleStore ps(*d, grid, blk.p.size());
        ps.upload(blk.p);
        CellPipeline cells(*d, grid);
        Physics phys(*d, grid, s);
        phys.set_floating(table);
        cells.run(ps);
        const Particles before = ps.download();  // sorted order, float-rounded values
        const std::size_t n = before.size();
        phys.enqueue_floating(ps, cells);  // allocates the force buffer
        std::vector<std::int64_t> unused;
        phys.add_floating_sums(unused);
        d->fill(phys.floating_force(), std::numeric_limits<float>::quiet_NaN(), 4 * ps.capacity());  // poison
        const std::size_t partials = phys.floating_partial_count();
        d->fill(phys.floating_partials(), cl_long{0x5a5a5a5a5a5a5a5a}, partials);
        phys.enqueue_floating(ps, cells);
        std::vector<float> got(4 * n);
        d->read(phys.floating_force(), got.data(), got.size());
        std::vector<std::int64_t> sums;
        phys.add_floating_sums(sums);
        REQUIRE(sums.size() == 24u);

        std::vector<std::array<double, 3>> want;
        std::vector<double> scale;
        cpu_forces(s, before, blk.body, want, scale);
        std::size_t bad = 0, body_particles = 0;
        std::int64_t expect[24] = {};
        double cpu_sum[2][12] = {}, sum_scale[2][12] = {};  // the sums, and of their terms' round-off scales
        for (std::size_t i = 0; i < n; ++i) {
            const int b = before.type[i] == ParticleType::boundary ? blk.body[before.id[i]] : -1;
            body_particles += b >= 0;
            for (int k = 0; k < 3; ++k) {
                const double g = got[4 * i + k], w = b >= 0 ? want[i][k] : 0.0;
                if (!(std::abs(g - w) <= 2e-5 * scale[i] + 1e-12) && bad++ < 8)
                    FAIL_CHECK("particle " << before.id[i] << " (body " << b << ") component " << k << ": device " << g << ", CPU " << w);
            }
            if (b < 0) continue;
            const float* f = &got[4 * i];
            const float* r0 = &table.body_rest[4 * before.id[i]];
            for (int k = 0; k < 3; ++k) {
                expect[12 * b + k] += fix(f[k]);
                cpu_sum[b][k] += want[i][k];
                sum_scale[b][k] += scale[i];
            }
            for (int a = 0; a < 3; ++a)
                for (int k = 0; k < 3; ++k) {
                    expect[12 * b + 3 + 3 * a + k] += fix(r0[a] * f[k]);
                    cpu_sum[b][3 + 3 * a + k] += double(r0[a]) * want[i][k];
                    sum_scale[b][3 + 3 * a + k] += std::abs(double(r0[a])) * scale[i];
                }
        }
        CHECK(bad == 0);
        CHECK(body_particles == 27u + 12u);
        for (int k = 0; k < 24; ++k) {
            CAPTURE(k);
            CHECK(sums[static_cast<std::size_t>(k)] == expect[k]);  // the integer sums, bit for bit
            const double sum = static_cast<double>(sums[static_cast<std::size_t>(k)]) / multi::kBodyFixedScale;
            // Each term within its round-off, and 2^-32 a term of fixed point.
            CHECK(std::abs(sum - cpu_sum[k / 12][k % 12]) <= 2e-5 * sum_scale[k / 12][k % 12] + 39 * 2.4e-10);
        }
        double total = 0;
        for (int k = 0; k < 3; ++k) total += std::abs(cpu_sum[0][k]);
        CHECK(total > 1e-3);  // the inputs give the bodies a force to compare
    }
}

TEST_CASE("floating bodies: the host's force, torque and accelerations from the fixed-point sums") {
    Scene s;
    s.physics.dp = 0.05;
    s.domain.min = {0, 0, 0};
    s.domain.max = {1, 1, 1};
    SolidBox box;
    box.min = {0.3, 0.3, 0.3};
    box.max = {0.5, 0.6, 0.4};
    box.layers = 0;
    box.floating.enabled = true;
    box.floating.density = 700;
    s.solids.push_back(box);
    multi::RigidBodies rb(s);
    REQUIRE(rb.size() == 1);
    auto gen = test::rng(3201);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto st = rb.states();
    std::array<double, 4> q{u(gen), u(gen), u(gen), u(gen)};
    const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (auto& c : q) c /= len;
    st[0].q_p = q;
    st[0].w_p = {0, 0, 0};
    rb.set_states(st);
    const auto R = multi::RigidBodies::rotation(q);
    std::vector<std::int64_t> sums(12, 0);
    std::array<double, 3> force{}, torque{};
    for (int i = 0; i < 50; ++i) {
        const float f[3] = {float(u(gen)), float(u(gen)), float(u(gen))}, r0[3] = {float(0.1 * u(gen)), float(0.1 * u(gen)), float(0.1 * u(gen))};
        for (int k = 0; k < 3; ++k) sums[static_cast<std::size_t>(k)] += fix(f[k]);
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < 3; ++k) sums[static_cast<std::size_t>(3 + 3 * a + k)] += fix(r0[a] * f[k]);
        double r[3];
        for (int a = 0; a < 3; ++a) r[a] = R[3 * a] * r0[0] + R[3 * a + 1] * r0[1] + R[3 * a + 2] * r0[2];
        for (int k = 0; k < 3; ++k) force[k] += f[k];
        torque[0] += r[1] * f[2] - r[2] * f[1];
        torque[1] += r[2] * f[0] - r[0] * f[2];
        torque[2] += r[0] * f[1] - r[1] * f[0];
    }
    rb.set_forces(sums);
    const auto& out = rb.states()[0];
    const double mass = rb.bodies()[0].mass;
    for (int k = 0; k < 3; ++k) {
        CHECK(out.force[k] == doctest::Approx(force[k]).epsilon(1e-6));
        CHECK(out.torque[k] == doctest::Approx(torque[k]).epsilon(1e-5).scale(1e-6));
        CHECK(out.a_new[k] == doctest::Approx(force[k] / mass + s.physics.gravity[k]).epsilon(1e-6));
    }
}
}
