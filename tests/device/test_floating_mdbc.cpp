// mDBC walls on a floating body (issue 32; kernels/motion.cl turn_ghost_nodes, kernels/mdbc.cl): a
// filled floating box put at a random pose (turned and moved, as the host's rigid-body state puts
// it) takes each particle's density from its ghost node turned with the body, against the CPU
// reference (support/mdbc_reference.hpp) on random fluid, on every device, in the fine and the CPU
// (lanes) forms; densities poisoned so that unwritten ones show. The box's ghost nodes at rest: every
// face mirrored (none counts as covered), nothing for particles deeper than a support. And the
// body's force from a force pass balances the fluid's (the densities it used are those the fluid
// felt, not the mDBC pass's that follows).
#include "device/cell_pipeline.hpp"
#include "device/floating_table.hpp"
#include "device/motion_table.hpp"
#include "device/physics.hpp"
#include "multi/rigid_bodies.hpp"
#include "scene/floating.hpp"
#include "scene/ghost_nodes.hpp"
#include "support/mdbc_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace clsph;

namespace {
// A filled floating box of density 500 in an open domain with mDBC walls (dp 0.02, a support of
// 3 dp), and a small block of fluid far from it (the scene needs fluid; each test adds its own).
Scene floating_box_scene(const Vec3& min, const Vec3& max, double alpha_wall) {
    Scene s;
    s.physics.dp = 0.02;
    s.physics.hdp = 1.5;
    s.physics.c0 = 20.0;
    s.physics.alpha_wall = alpha_wall;
    s.boundary_method = BoundaryMethod::mdbc;
    s.domain.min = {-0.15, -0.15, -0.15};
    s.domain.max = {0.45, 0.35, 0.35};
    SolidBox b;
    b.min = min;
    b.max = max;
    b.layers = 0;
    b.floating.enabled = true;
    b.floating.density = 500;
    s.solids.push_back(b);
    FluidBlock far;
    far.min = {0.36, 0.26, 0.26};
    far.max = {0.4, 0.3, 0.3};
    s.fluids.push_back(far);
    s.validate();
    return s;
}
}  // namespace

TEST_SUITE("floating") {
TEST_CASE("mDBC on a floating box: ghost nodes turned and moved with the body, against the CPU, on every device") {
    // 8 x 7 x 8 lattice points: its centre deeper than a support (3 dp) from every face.
    const Scene s = floating_box_scene({0.06, 0.04, 0.03}, {0.20, 0.16, 0.17}, Scene().physics.alpha_wall);
    const device::Grid grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), 0, {false, false, false},
                            device::reach_for(s.physics.support(), s.physics.dp));
    const Particles built = s.build_particles();
    const auto bodies = scene::floating_bodies(s);
    REQUIRE(bodies.size() == 1);
    const Vec3 c0 = bodies[0].centre;
    const float poison = std::numeric_limits<float>::quiet_NaN();
    Particles p;
    for (std::size_t i = 0; i < built.size(); ++i)
        if (built.type[i] == ParticleType::boundary) p.push_back(built.id[i], built.type[i], built.position[i], {0, 0, 0}, poison, 0.0f);
    const std::size_t nb = p.size();
    REQUIRE(nb == 8u * 7u * 8u);
    const auto offsets = scene::ghost_node_offsets(s, p);
    std::vector<std::array<float, 3>> by_id(nb);
    std::size_t face = 0, deep = 0;
    for (std::size_t i = 0; i < nb; ++i) {
        by_id[p.id[i]] = offsets[i];
        const auto& g = offsets[i];
        const double len = std::sqrt(double(g[0]) * g[0] + double(g[1]) * g[1] + double(g[2]) * g[2]);
        face += std::abs(len - s.physics.dp) < 1e-6;
        deep += len == 0;
        for (int k = 0; k < 3; ++k) CHECK(std::abs(g[k]) < 2 * s.physics.support());  // at most 5 dp out along a normal
    }
    // Mirrored dp out through one face only: on a face and 3 dp deep from the other four (x, z: 2
    // of 8 points; y: 1 of 7); deeper than 3 dp from every face: none.
    CHECK(face == 2u * (1 * 2) + 2u * (2 * 2) + 2u * (2 * 1));
    CHECK(deep == 2u * 1u * 2u);

    // The body's pose: a random orientation, moved a little; random fluid all around it.
    auto gen = test::rng(3202);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::array<double, 4> q{u(gen), u(gen), u(gen), u(gen)};
    const double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (auto& c : q) c /= ql;
    const auto R = multi::RigidBodies::rotation(q);
    const Vec3 T{0.02 * u(gen), 0.02 * u(gen), 0.02 * u(gen)};
    std::array<double, 18> pose{};
    for (int k = 0; k < 9; ++k) pose[k] = R[k];
    for (int k = 0; k < 3; ++k) pose[9 + k] = T[k];
    MESSAGE("the body turned by the quaternion " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << ", moved by "
                                                  << T[0] << " " << T[1] << " " << T[2]);
    auto turn = [&](const std::array<double, 3>& v) {
        return Vec3{R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
                    R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
    };
    std::uniform_real_distribution<double> ux(-0.05, 0.31), uyz(-0.08, 0.28), rho(990.0, 1010.0);
    for (int k = 0; k < 5000; ++k)
        p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, {ux(gen), uyz(gen), uyz(gen)}, {0, 0, 0},
                    static_cast<float>(rho(gen)), 0.0f);
    for (auto* d : test::devices()) {
        for (const Interaction form : {Interaction::fine, Interaction::lanes}) {
            CAPTURE(d->label());
            CAPTURE(form == Interaction::lanes);
            device::Physics phys(*d, grid, s, form);
            device::MotionTable table;
            const auto floating = device::add_floating(table, s, grid);
            phys.set_motion(table);
            phys.set_floating(floating);
            phys.set_ghost_nodes(by_id);
            phys.set_floating_poses({pose});
            device::CellPipeline cells(*d, grid);
            device::ParticleStore ps(*d, grid, p.size());
            ps.upload(p);
            cells.run(ps);
            phys.move_solids(ps, 0.0, 0.0, 1.0);
            cells.run(ps);
            phys.boundary_densities(ps, cells);
            const Particles got = ps.download();
            REQUIRE(got.size() == p.size());
            std::size_t wrong = 0, misplaced = 0, unturned_differs = 0, with_fluid = 0;
            for (std::size_t i = 0; i < got.size(); ++i) {
                if (got.type[i] != ParticleType::boundary) continue;
                const std::size_t id = got.id[i];
                // Where the body put it: C0 + T + R r0.
                const Vec3 r = turn({p.position[id][0] - c0[0], p.position[id][1] - c0[1], p.position[id][2] - c0[2]});
                for (int k = 0; k < 3; ++k) misplaced += std::abs(got.position[i][k] - (c0[k] + T[k] + r[k])) > 1e-5;
                const auto& g0 = by_id[id];
                const Vec3 g = turn({g0[0], g0[1], g0[2]});
                const std::array<float, 3> mirror{static_cast<float>(g[0]), static_cast<float>(g[1]), static_cast<float>(g[2])};
                const auto ref = test::reference_density(p, s, phys.params(), got.position[i], mirror);
                if (ref.det != 0 && std::abs(std::abs(ref.det) - CLSPH_MDBC_DET) < 0.02 * CLSPH_MDBC_DET) continue;
                const auto stale = test::reference_density(p, s, phys.params(), got.position[i], g0);
                with_fluid += ref.det != 0;
                unturned_differs += std::abs(stale.rho - ref.rho) > 0.5;
                const bool ok = std::abs(got.density[i] - ref.rho) <= 0.05;  // a NaN (unwritten) fails
                if (!ok && wrong < 5) MESSAGE("body particle id " << id << ": device " << got.density[i] << ", CPU " << ref.rho);
                wrong += !ok;
            }
            MESSAGE(nb << " body particles, " << with_fluid << " with fluid at their ghost node; " << unturned_differs
                       << " would differ by > 0.5 kg/m^3 with the offsets at rest");
            CHECK(misplaced == 0);
            CHECK(wrong == 0);
            CHECK(with_fluid > 100);
            CHECK(unturned_differs > 0);  // the test tells turned from unturned offsets
        }
    }
}
}

TEST_SUITE("floating") {
// The body's force is the reaction of the fluid's (the pair terms are antisymmetric, fluid-fluid
// ones cancel): after one force pass with mDBC, the fluid's total force sum m (a - g) is minus the
// body's fixed-point sum F, to round-off. The mDBC pass of the same call changes the body's
// densities (given 1030 here, far from what the fluid around gives): a body force from those
// would not balance. With no-slip walls and laminar viscosity the fluid sees the body's particles
// at their velocity plus a random v_wall - v_G of an earlier pass (kernels/wall_velocity.h), and
// the body's force must be the reaction of those same terms.
TEST_CASE("mDBC on a floating box: its force balances the fluid's, from the densities the fluid felt, on every device") {
  for (const bool no_slip : {false, true}) {
    CAPTURE(no_slip);
    Scene s = floating_box_scene({0.08, 0.06, 0.06}, {0.16, 0.14, 0.14}, 0.3);
    if (no_slip) {
        s.wall_slip = WallSlip::no_slip;
        s.physics.viscosity = Viscosity::laminar;
        s.physics.kinematic_viscosity = 1e-2;  // the viscous terms worth as much as the pressure's
    }
    const SolidBox& b = s.solids.back();
    const device::Grid grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), 0, {false, false, false},
                            device::reach_for(s.physics.support(), s.physics.dp));
    const Particles built = s.build_particles();
    auto gen = test::rng(3203);
    // The fluid is denser on the box's -x side than on its +x side, so the pressure pushes the body
    // towards +x whatever the seed (a fluid of one density around it gives a net force of a few
    // terms' round-off only, too small to compare with some seeds).
    std::uniform_real_distribution<double> jitter(-0.2, 0.2), vel(-0.3, 0.3), rho_high(1040.0, 1050.0), rho_low(995.0, 1005.0);
    const double centre_x = 0.5 * (b.min[0] + b.max[0]);
    Particles p;
    for (std::size_t i = 0; i < built.size(); ++i)
        if (built.type[i] == ParticleType::boundary)
            p.push_back(built.id[i], built.type[i], built.position[i], {0.1f, 0.0f, -0.2f}, 1030.0f, 0.0f);
    const std::size_t nb = p.size();
    const double dp = s.physics.dp;
    for (int i = -4; i <= 12; ++i)
        for (int j = -4; j <= 12; ++j)
            for (int k = -4; k <= 12; ++k) {
                const Vec3 x{0.0 + i * dp + jitter(gen) * dp, 0.0 + j * dp + jitter(gen) * dp, 0.0 + k * dp + jitter(gen) * dp};
                bool near = true;  // keep dp from the box
                for (int a = 0; a < 3; ++a) near = near && x[a] > b.min[a] - dp && x[a] < b.max[a] + dp;
                if (near) continue;
                p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, x,
                            {float(vel(gen)), float(vel(gen)), float(vel(gen))},
                            float(x[0] < centre_x ? rho_high(gen) : rho_low(gen)), 0.0f);
            }
    const auto offsets = scene::ghost_node_offsets(s, p);
    std::vector<std::array<float, 3>> by_id(nb);
    for (std::size_t i = 0; i < nb; ++i) by_id[p.id[i]] = offsets[i];
    const double m = s.physics.rho0 * dp * dp * dp;
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        device::Physics phys(*d, grid, s);
        device::MotionTable table;
        const auto floating = device::add_floating(table, s, grid);
        phys.set_motion(table);
        phys.set_floating(floating);
        phys.set_ghost_nodes(by_id);
        device::CellPipeline cells(*d, grid);
        device::ParticleStore ps(*d, grid, p.size());
        ps.upload(p);
        cells.run(ps);
        REQUIRE(phys.no_slip() == no_slip);
        if (no_slip) {  // what an earlier mDBC pass left the walls (the fluid's entries are not read)
            std::uniform_real_distribution<float> dv(-2.0f, 2.0f);
            std::vector<float> seen(4 * ps.capacity(), 0.0f);
            for (float& x : seen) x = dv(gen);
            d->write(ps.accel, seen.data(), seen.size());
        }
        // Forces, the body's force, then the mDBC pass (no-slip: not into the accelerations it reads).
        cl_rt::Buffer& out = no_slip ? ps.scratch : ps.accel;
        phys.forces(ps, cells, out);
        std::vector<std::int64_t> sums;
        phys.add_floating_sums(sums);
        REQUIRE(sums.size() == 12u);
        const Particles got = ps.download();
        std::vector<float> acc(4 * got.size());
        d->read(out, acc.data(), acc.size(), 4 * ps.ranges.first_owned());
        double fluid[3] = {0, 0, 0}, scale = 0, moved = 0;
        for (std::size_t i = 0; i < got.size(); ++i) {
            if (got.type[i] != ParticleType::fluid) {
                moved += std::abs(got.density[i] - 1030.0) / static_cast<double>(nb);
                continue;
            }
            for (int k = 0; k < 3; ++k) {
                const double f = m * (acc[4 * i + static_cast<std::size_t>(k)] - s.physics.gravity[k]);
                fluid[k] += f;
                scale += std::abs(f);
            }
        }
        double body[3], worst = 0, size = 0;
        for (int k = 0; k < 3; ++k) {
            body[k] = static_cast<double>(sums[static_cast<std::size_t>(k)]) / multi::kBodyFixedScale;
            worst = std::max(worst, std::abs(fluid[k] + body[k]));
            size += std::abs(body[k]);
        }
        MESSAGE("body force " << body[0] << " " << body[1] << " " << body[2] << " N, fluid's " << fluid[0] << " " << fluid[1]
                              << " " << fluid[2] << " N (sum of |terms| " << scale << "); the mDBC pass moved the body's densities by "
                              << moved << " kg/m^3 on average");
        CHECK(body[0] > 1e-3 * scale);         // the body feels the push towards +x, a force worth comparing
        CHECK(worst <= 1e-5 * scale + 1e-7);   // Newton's third law, to float round-off
        CHECK(moved > 5.0);                    // the densities after the pass differ: the order matters
    }
  }
}
}
