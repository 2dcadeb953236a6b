// Prescribed motion of solids (issue 32; kernels/motion.cl, scene/motion.cpp): each segment type
// moves a solid's boundary particles as its closed form computed here in double has them (within
// float), on every device, on 2 devices while the cuts sweep across the solid, bitwise the same on
// 1 and 2 devices and in the step ahead; the wall's speed bounds the time step.
#include "clsph/checkpoint.hpp"
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "device/cell_pipeline.hpp"
#include "device/motion_table.hpp"
#include "device/physics.hpp"
#include "scene/ghost_nodes.hpp"
#include "scene/motion.hpp"
#include "support/mdbc_reference.hpp"
#include "support/cut_schedules.hpp"
#include "support/scenes.hpp"
#include "support/bitwise_state.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>

using namespace clsph;

namespace {

using Type = MotionSegment::Type;

// The small tank with water at its x- end and a paddle (a filled box) in the middle, moved by
// one segment of `type` with random parameters, starting within the first steps and ending
// before the run does (so the rest after it is tested too).
Scene paddle_tank(Type type, std::mt19937_64& rng) {
    Scene s = test::small_tank(0.08, 0.1);
    SolidBox b;
    b.min = {0.14, 0.03, 0.04};
    b.max = {0.17, 0.07, 0.16};
    b.layers = 0;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MotionSegment m;
    m.type = type;
    m.start = 0.001 + 0.001 * (u(rng) + 1.0);
    m.end = m.start + 0.003 + 0.0015 * (u(rng) + 1.0);
    m.period = 0.012 + 0.004 * u(rng);
    m.phase = 3.0 * u(rng);
    m.velocity = {1.0 * u(rng), 0.3 * u(rng), 0.5 * u(rng)};
    m.amplitude = {0.003 * u(rng), 0.002 * u(rng), 0.002 * u(rng)};
    m.axis_point = {0.155 + 0.01 * u(rng), 0.05, 0.1 + 0.01 * u(rng)};
    m.axis = {u(rng), u(rng), 1.0 + u(rng)};
    m.angle = 0.05 * u(rng);
    m.angular_velocity = 20.0 * u(rng);
    b.motion.segments.push_back(m);
    s.solids.push_back(b);
    s.validate();
    return s;
}

const char* type_name(Type t) {
    static const char* names[] = {"linear", "sine", "sine_rotation", "rotation", "linear_rotation", "ramped_sine", "ramped_sine_rotation"};
    return names[static_cast<int>(t)];
}

// Particles by id.
std::map<std::uint32_t, std::size_t> by_id(const Particles& p) {
    std::map<std::uint32_t, std::size_t> m;
    for (std::size_t i = 0; i < p.size(); ++i) m[p.id[i]] = i;
    return m;
}

// Every boundary particle after the steps so far: the paddle's where the closed form puts it
// (position within 2e-6 m, velocity within 1e-5 (1 + |v|)), the rest where they were.
void check_state(Simulation& sim, const Scene& scene, const Particles& p0) {
    const auto& motion = scene.solids[0].motion;
    const auto& box = scene.solids[0];
    const double t = sim.time();
    const Particles p = sim.particles();
    const auto index = by_id(p);
    const scene::RigidPose pose = scene::motion_pose(motion, t);
    double worst_x = 0, worst_v = 0, speed = 0;
    std::size_t paddle = 0;
    for (std::size_t i = 0; i < p0.size(); ++i) {
        if (p0.type[i] != ParticleType::boundary) continue;
        const auto it = index.find(p0.id[i]);
        REQUIRE(it != index.end());
        const auto& x0 = p0.position[i];
        bool in_box = true;
        for (int k = 0; k < 3; ++k) in_box = in_box && x0[k] >= box.min[k] - 1e-9 && x0[k] <= box.max[k] + 1e-9;
        paddle += in_box;
        const Vec3 want = in_box ? pose.apply(x0) : x0;
        const Vec3 want_v = in_box ? scene::motion_velocity(motion, t, x0) : Vec3{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            worst_x = std::max(worst_x, std::abs(p.position[it->second][k] - want[k]));
            worst_v = std::max(worst_v, std::abs(p.velocity[it->second][k] - want_v[k]) / (1.0 + std::abs(want_v[k])));
            speed = std::max(speed, std::abs(want_v[k]));
        }
    }
    MESSAGE("t = " << t << " s, " << paddle << " paddle particles (speed " << speed << " m/s), worst position " << worst_x
                   << " m, velocity " << worst_v);
    CHECK(paddle == 13u * 5u * 4u);  // 4 x 5 x 13 lattice points in the box
    CHECK(worst_x < 2e-6);
    CHECK(worst_v < 1e-5);
}

// Runs `steps` steps, checking every 5 steps: before, during and after the segment.
void check_run(const Scene& scene, const Options& o, int steps) {
    Simulation sim(scene, o);
    const Particles p0 = sim.particles();
    for (int k = 1; k <= steps; ++k) {
        sim.step();
        if (k % 5 == 0) check_state(sim, scene, p0);
    }
    CHECK(sim.time() > scene.solids[0].motion.segments[0].end);  // the run went past the segment: the rest after it too
}

using test::differing;
using test::state_of;

Options two_with_sweeping_cuts() {
    Options o;
    o.devices = test::device_spec(2);
    testing::Seams seams;
    seams.cut_schedule = test::sweeping_cuts(2);
    testing::set_seams(o, seams);
    return o;
}

}  // namespace

TEST_SUITE("motion") {
TEST_CASE("each motion type moves a solid as its closed form, on every device") {
    for (Type type : {Type::linear, Type::sine, Type::sine_rotation, Type::rotation}) {
        auto rng = test::rng(11 + static_cast<int>(type));
        const Scene scene = paddle_tank(type, rng);
        for (auto* dev : test::devices()) {
            const std::string name = type_name(type);
            CAPTURE(name);
            CAPTURE(dev->label());
            Options o;
            o.devices = std::to_string(dev->info().index);
            check_run(scene, o, 30);
        }
    }
}

TEST_CASE("Symplectic: the half step and the full step both put the solid by its formula") {
    auto rng = test::rng(21);
    Scene scene = paddle_tank(Type::sine_rotation, rng);
    scene.physics.integrator = Integrator::symplectic;
    Options o;
    o.devices = test::device_spec(1);
    check_run(scene, o, 45);
}

TEST_CASE("a moving solid across sweeping slab cuts on 2 devices, bitwise the same as on 1") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    for (Type type : {Type::linear, Type::rotation}) {
        const std::string name = type_name(type);
        CAPTURE(name);
        auto rng = test::rng(31 + static_cast<int>(type));
        const Scene scene = paddle_tank(type, rng);
        check_run(scene, two_with_sweeping_cuts(), 30);
        Options one;
        one.devices = test::device_spec(1);
        Simulation a(scene, one), b(scene, two_with_sweeping_cuts());
        for (int k = 0; k < 30; ++k) {
            a.step();
            b.step();
        }
        CHECK(a.time() == b.time());
        CHECK(differing(state_of(a), state_of(b)) == 0);
    }
}

// The paddle standing in the water (fluid on both sides of it), walls and paddle by mDBC.
Scene mdbc_paddle_tank(Type type, std::mt19937_64& rng) {
    Scene s = paddle_tank(type, rng);
    s.boundary_method = BoundaryMethod::mdbc;
    s.fluids.front().max = {0.13, 0.1, 0.1};
    FluidBlock f = s.fluids.front();
    f.min = {0.18, 0, 0};
    f.max = {0.3, 0.1, 0.1};
    s.fluids.push_back(f);
    s.validate();
    return s;
}

TEST_CASE("mDBC: a flap in the water moves as its formula, bitwise the same on 1 and 2 devices while cuts sweep") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    for (Type type : {Type::sine_rotation, Type::linear}) {
        const std::string name = type_name(type);
        CAPTURE(name);
        auto rng = test::rng(61 + static_cast<int>(type));
        const Scene scene = mdbc_paddle_tank(type, rng);
        for (auto* dev : devs) {
            CAPTURE(dev->label());
            Options o;
            o.devices = std::to_string(dev->info().index);
            check_run(scene, o, 30);
        }
        Options one;
        one.devices = test::device_spec(1);
        Simulation a(scene, one), b(scene, two_with_sweeping_cuts());
        for (int k = 0; k < 30; ++k) {
            a.step();
            b.step();
        }
        CHECK(a.time() == b.time());
        CHECK(differing(state_of(a), state_of(b)) == 0);
    }
}

TEST_CASE("mDBC no-slip walls: a flap moves as its formula and every wall keeps its own velocity, bitwise on 1 and 2 devices") {
    // The mirrored velocities live in the boundary particles' accelerations (kernels/wall_velocity.h):
    // the motion's velocities (and the still walls' zeros) that frames show are the walls' own.
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    auto rng = test::rng(67);
    Scene scene = mdbc_paddle_tank(Type::sine_rotation, rng);
    scene.wall_slip = WallSlip::no_slip;
    scene.physics.viscosity = Viscosity::laminar;
    scene.physics.kinematic_viscosity = 1e-3;
    Options one;
    one.devices = test::device_spec(1);
    check_run(scene, one, 30);
    Simulation a(scene, one), b(scene, two_with_sweeping_cuts());
    for (int k = 0; k < 30; ++k) {
        a.step();
        b.step();
    }
    CHECK(a.time() == b.time());
    CHECK(differing(state_of(a), state_of(b)) == 0);
}

TEST_CASE("mDBC: a turned solid's ghost nodes turn with it: its densities as plain C++ has them") {
    // A box turned 0.7 rad about a skew axis through its centre, in random fluid around it; and the
    // same turn with the axis moving (linear_rotation, a CSV interval) and ramped (a flap wave maker).
    for (Type type : {Type::rotation, Type::linear_rotation, Type::ramped_sine_rotation}) {
        const std::string name = type_name(type);
        CAPTURE(name);
        Scene s;
        s.physics.dp = 0.02;
        s.physics.c0 = 20.0;
        s.boundary_method = BoundaryMethod::mdbc;
        s.domain.min = {-0.1, -0.1, -0.1};
        s.domain.max = {0.4, 0.3, 0.3};
        SolidBox b;
        b.min = {0.1, 0.04, 0.04};
        b.max = {0.2, 0.16, 0.16};
        MotionSegment m;
        m.type = Type::rotation;
        m.start = 0;
        m.end = 10;
        m.axis_point = {0.15, 0.1, 0.1};
        m.axis = {0.3, 1, 0.5};
        m.angular_velocity = 1.0;
        if (type != Type::rotation) {
            m.type = type;
            m.velocity = {0.01, -0.005, 0.004};  // linear_rotation: the axis drifts a little
            m.period = 4.0, m.ramp = 0.3, m.angle = 0.9;  // ramped: 0.9 sin(2 pi 0.7 / 4) = 0.80 rad at t = 0.7
        }
        b.motion.segments.push_back(m);
        s.solids.push_back(b);
        FluidBlock f;
        f.min = {0.3, 0.2, 0.2};
        f.max = {0.34, 0.24, 0.24};
        s.fluids.push_back(f);
        s.validate();
        const double t = 0.7;
        const device::Grid grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), 0, {false, false, false},
                                device::reach_for(s.physics.support(), s.physics.dp));
        const Particles built = s.build_particles();
        Particles p;
        for (std::size_t i = 0; i < built.size(); ++i)
            if (built.type[i] == ParticleType::boundary)
                p.push_back(built.id[i], built.type[i], built.position[i], {0, 0, 0}, 1000.0f, 0.0f);
        const std::size_t nb = p.size();
        const auto offsets = scene::ghost_node_offsets(s, p);
        std::vector<std::array<float, 3>> by_id(nb);
        for (std::size_t i = 0; i < nb; ++i) by_id[p.id[i]] = offsets[i];
        auto gen = test::rng(71);
        std::uniform_real_distribution<double> ux(0.02, 0.28), uyz(-0.04, 0.24), rho(990.0, 1010.0);
        for (int k = 0; k < 4000; ++k)
            p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, {ux(gen), uyz(gen), uyz(gen)}, {0, 0, 0},
                        static_cast<float>(rho(gen)), 0.0f);
        const scene::RigidPose pose = scene::motion_pose(s.solids[0].motion, t);
        for (auto* d : test::devices()) {
            CAPTURE(d->label());
            device::Physics phys(*d, grid, s);
            phys.set_motion(device::motion_table(s, grid));
            phys.set_ghost_nodes(by_id);
            device::CellPipeline cells(*d, grid);
            device::ParticleStore ps(*d, grid, p.size());
            ps.upload(p);
            cells.run(ps);
            phys.move_solids(ps, t, 0.0, 1.0);
            cells.run(ps);
            phys.boundary_densities(ps, cells);
            const Particles got = ps.download();
            REQUIRE(got.size() == p.size());
            std::size_t wrong = 0, unturned_differs = 0, with_fluid = 0;
            for (std::size_t i = 0; i < got.size(); ++i) {
                if (got.type[i] != ParticleType::boundary) continue;
                const auto& g0 = by_id[got.id[i]];
                const Vec3 turned = scene::RigidPose{pose.R, {0, 0, 0}}.apply({g0[0], g0[1], g0[2]});
                const std::array<float, 3> mirror{static_cast<float>(turned[0]), static_cast<float>(turned[1]), static_cast<float>(turned[2])};
                const auto ref = test::reference_density(p, s, phys.params(), got.position[i], mirror);
                if (ref.det != 0 && std::abs(std::abs(ref.det) - CLSPH_MDBC_DET) < 0.02 * CLSPH_MDBC_DET) continue;
                const auto stale = test::reference_density(p, s, phys.params(), got.position[i], g0);
                with_fluid += ref.det != 0;
                unturned_differs += std::abs(stale.rho - ref.rho) > 0.5;
                const bool ok = std::abs(got.density[i] - ref.rho) <= 0.05;
                if (!ok && wrong < 5) MESSAGE("boundary id " << got.id[i] << ": device " << got.density[i] << ", CPU " << ref.rho);
                wrong += !ok;
            }
            MESSAGE(nb << " boundary particles, " << with_fluid << " with fluid at their ghost node; " << unturned_differs
                       << " would differ by > 0.5 kg/m^3 with the offsets at rest");
            CHECK(wrong == 0);
            CHECK(with_fluid > 0);
            CHECK(unturned_differs > 0);  // the test tells turned from unturned offsets
        }
    }
}

TEST_CASE("the step ahead moves solids bitwise as the synchronous path does") {
    auto rng = test::rng(41);
    const Scene scene = paddle_tank(Type::sine, rng);
    Options sync, ahead;
    sync.devices = ahead.devices = test::device_spec(1);
    ahead.synchronous = false;
    Simulation a(scene, sync), b(scene, ahead);
    const double t = 0.01;
    a.run_until(t);
    b.run_until(t);
    CHECK(a.time() == b.time());
    CHECK(differing(state_of(a), state_of(b)) == 0);
}

TEST_CASE("a run resumed from a checkpoint with the solid moved goes on bitwise as the straight run") {
    auto rng = test::rng(51);
    const Scene scene = paddle_tank(Type::rotation, rng);
    Options o;
    o.devices = test::device_spec(1);
    Simulation straight(scene, o);
    for (int i = 0; i < 20; ++i) straight.step();
    Simulation first(scene, o);
    for (int i = 0; i < 8; ++i) first.step();  // mid-segment: the paddle has turned
    const Checkpoint c = first.checkpoint();
    Simulation resumed(scene, c, o);
    for (int i = 0; i < 12; ++i) resumed.step();
    CHECK(straight.time() == resumed.time());
    CHECK(differing(state_of(straight), state_of(resumed)) == 0);
}

TEST_CASE("the wall's speed bounds the time step") {
    // A fast paddle (5 m/s, half the speed of sound) in still water: the step shrinks by c0 / (c0 + |v|).
    Scene scene = test::small_tank(0.08, 0.1);
    SolidBox b;
    b.min = {0.14, 0.03, 0.04};
    b.max = {0.17, 0.07, 0.16};
    b.layers = 0;
    MotionSegment m;
    m.type = Type::linear;
    m.start = 0;
    m.end = 1;
    m.velocity = {0, 0, 5.0};
    b.motion.segments.push_back(m);
    Scene moving_scene = scene, resting_scene = scene;
    moving_scene.solids.push_back(b);
    b.motion.segments.back().velocity = {0, 0, 0};  // the same segment, at rest
    resting_scene.solids.push_back(b);
    Options o;
    o.devices = test::device_spec(1);
    Simulation moving(moving_scene, o), resting(resting_scene, o);
    moving.step();
    resting.step();
    const double dt_moving = moving.step().dt, dt_resting = resting.step().dt;
    const double c0 = scene.sound_speed();
    MESSAGE("dt " << dt_moving << " moving, " << dt_resting << " at rest, c0 " << c0);
    CHECK(dt_moving < dt_resting * (c0 + 1.0) / (c0 + 5.0) * 1.05);
}
}
