// Motions from elsewhere on the devices (issue 32 items 1 and 2; kernels/motion.cl): a solid
// moved by a CSV file written here (many linear_rotation intervals, found by binary search in the
// table, a second moving solid beside it) and the wave makers' ramped segments move their
// boundary particles as the closed form computed here in double has them, on every device.
#include "clsph/simulation.hpp"
#include "scene/motion.hpp"
#include "scene/motion_csv.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

using namespace clsph;

namespace {

using Type = MotionSegment::Type;

// The small tank with water at its x- end and two paddles (filled boxes), moved by `a` and `b`.
Scene two_paddles(const Motion& a, const Motion& b) {
    Scene s = test::small_tank(0.08, 0.1);
    SolidBox p;
    p.min = {0.14, 0.03, 0.04};
    p.max = {0.17, 0.07, 0.16};
    p.layers = 0;
    p.motion = a;
    s.solids.push_back(p);
    p.min = {0.22, 0.03, 0.04};
    p.max = {0.25, 0.07, 0.1};
    p.motion = b;
    s.solids.push_back(p);
    s.validate();
    return s;
}

bool inside(const Vec3& x, const SolidBox& b) {
    for (int k = 0; k < 3; ++k)
        if (x[k] < b.min[k] - 1e-9 || x[k] > b.max[k] + 1e-9) return false;
    return true;
}

// Every boundary particle where the closed form puts it (position within 2e-6 m, velocity within
// 1e-5 (1 + |v|)), the still ones where they were.
void check_state(Simulation& sim, const Scene& scene, const Particles& p0) {
    const double t = sim.time();
    const Particles p = sim.particles();
    std::map<std::uint32_t, std::size_t> index;
    for (std::size_t i = 0; i < p.size(); ++i) index[p.id[i]] = i;
    double worst_x = 0, worst_v = 0, speed = 0;
    std::size_t moving = 0;
    for (std::size_t i = 0; i < p0.size(); ++i) {
        if (p0.type[i] != ParticleType::boundary) continue;
        const auto it = index.find(p0.id[i]);
        REQUIRE(it != index.end());
        const auto& x0 = p0.position[i];
        Vec3 want = x0, want_v{0, 0, 0};
        for (const auto& b : scene.solids)
            if (inside(x0, b)) {
                want = scene::motion_pose(b.motion, t).apply(x0);
                want_v = scene::motion_velocity(b.motion, t, x0);
                ++moving;
            }
        for (int k = 0; k < 3; ++k) {
            worst_x = std::max(worst_x, std::abs(p.position[it->second][k] - want[k]));
            worst_v = std::max(worst_v, std::abs(p.velocity[it->second][k] - want_v[k]) / (1.0 + std::abs(want_v[k])));
            speed = std::max(speed, std::abs(want_v[k]));
        }
    }
    MESSAGE("t = " << t << " s, " << moving << " moving particles (speed " << speed << " m/s), worst position " << worst_x
                   << " m, velocity " << worst_v);
    CHECK(moving == 13u * 5u * 4u + 7u * 5u * 4u);
    CHECK(worst_x < 2e-6);
    CHECK(worst_v < 1e-5);
}

void check_run(const Scene& scene, int steps) {
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        Options o;
        o.devices = std::to_string(dev->info().index);
        Simulation sim(scene, o);
        const Particles p0 = sim.particles();
        for (int k = 1; k <= steps; ++k) {
            sim.step();
            if (k % 5 == 0) check_state(sim, scene, p0);
        }
        CHECK(sim.time() > scene.solids[0].motion.segments.back().end);  // past the motion: its rest too
    }
}

}  // namespace

TEST_SUITE("motion") {
TEST_CASE("a motion from a CSV file moves a solid as its rows say, on every device (binary search over two solids' segments)") {
    auto rng = test::rng(71);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto path = std::filesystem::temp_directory_path() / ("clsph-motion-" + std::to_string(rng()) + ".csv");
    {
        std::ofstream out(path);
        out.precision(17);
        out << "time,x,y,z,rx,ry,rz\n";
        double t = 0.0005 + 0.0005 * (u(rng) + 1), x = 0, y = 0, z = 0, a = 0, b = 0, c = 0;
        for (int k = 0; k < 40; ++k) {
            out << t << "," << x << "," << y << "," << z << "," << a << "," << b << "," << c << "\n";
            t += 0.0001 + 0.0001 * (u(rng) + 1);
            x += 1e-4 * u(rng), y += 3e-5 * u(rng), z += 5e-5 * u(rng);
            a += 0.3 * u(rng), b += 0.3 * u(rng), c += 0.3 * u(rng);
        }
    }
    Motion csv;
    csv.segments = scene::csv_motion_segments(scene::read_motion_csv(path.string(), "test"), {0.155 + 0.01 * u(rng), 0.05, 0.1});
    std::filesystem::remove(path);
    Motion lin;
    MotionSegment s;
    s.type = Type::linear;
    s.start = 0.0005;
    s.end = 0.002;
    s.velocity = {0.3 * u(rng), 0.1 * u(rng), 0.2 * u(rng)};
    lin.segments.push_back(s);
    s.start = 0.003;
    s.end = 0.004;
    lin.segments.push_back(s);
    check_run(two_paddles(csv, lin), 40);
}

TEST_CASE("the wave makers' ramped segments move a solid as their closed form, on every device") {
    auto rng = test::rng(73);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MotionSegment piston;
    piston.type = Type::ramped_sine;
    piston.start = 0.0005 + 0.0005 * (u(rng) + 1);
    piston.end = piston.start + 0.004;
    piston.period = 0.004 + 0.001 * u(rng);
    piston.ramp = 0.002 + 0.0005 * u(rng);
    piston.amplitude = {0.002 * u(rng), 0.0005 * u(rng), 0.001 * u(rng)};
    MotionSegment flap = piston;
    flap.type = Type::ramped_sine_rotation;
    flap.amplitude = {0, 0, 0};
    flap.axis_point = {0.155 + 0.01 * u(rng), 0.05, 0.04};
    flap.axis = {u(rng), 1.0 + u(rng), 0.3 * u(rng)};
    flap.angle = 0.05 * u(rng);
    Motion a, b;
    a.segments.push_back(flap);
    b.segments.push_back(piston);
    check_run(two_paddles(a, b), 40);
}
}
