// Open boundaries in time and across (docs/scenes.md, inlets and outlets): the open channel of
// test_open_boundaries.cpp fed at a speed from a CSV file that ramps up and down, with a profile
// across the inlet and an outlet zone that holds a pressure. The buffer moves by exactly the
// travelled distance X(t + dt) - X(t) each step (against the test's own integral of the file's
// rows), the layers made are those the integral gives per lattice column, the zone holds Tait's
// density and nothing passes its face; 1 and 2 devices bitwise alike; a checkpoint mid-ramp
// resumes bitwise; a zone holding a level keeps the hydrostatic density below it.
#include "clsph/checkpoint.hpp"
#include "clsph/devices.hpp"
#include "clsph/memory_plan.hpp"
#include "clsph/scene_io.hpp"
#include "clsph/simulation.hpp"
#include "scene/time_series.hpp"
#include "support/bitwise_state.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

using namespace clsph;

namespace {

constexpr double kDp = test::kChannelDp;
// The file's rows: speed (m/s) at time (s); held after the last.
const std::vector<std::array<double, 2>> kRows{{0.0, 0.5}, {0.04, 0.75}, {0.1, 0.35}, {0.3, 0.45}};
constexpr double kZoneFace = 0.36, kZonePressure = 40.0;

// The speed file, written once per process, read by the reader speed_csv uses.
TimeSeries speed_from_csv() {
    const std::string path = (std::filesystem::temp_directory_path() / "clsph_test_open_ramp.csv").string();
    {
        std::ofstream f(path);
        f << "time, speed\n# a ramp up and down\n";
        for (const auto& r : kRows) f << r[0] << ", " << r[1] << "\n";
    }
    const TimeSeries s = scene::read_series_csv(path, "inlets[0].speed_csv", scene::SeriesColumn{"speed", "m/s", 0.0});
    std::remove(path.c_str());
    return s;
}

// The profile's factor at z (its points: 0.6 at z = 0, 1.2 at z = 0.1, linear between).
double factor_at(double z) { return 0.6 + 0.6 * std::min(1.0, std::max(0.0, z / 0.1)); }

// The rows' speed at t: linear between them, held beyond.
double speed_at(double x) {
    if (x >= kRows.back()[0]) return kRows.back()[1];
    std::size_t k = 0;
    while (kRows[k + 1][0] <= x) ++k;
    return kRows[k][1] + (kRows[k + 1][1] - kRows[k][1]) * (x - kRows[k][0]) / (kRows[k + 1][0] - kRows[k][0]);
}

// The test's own X(t): the midpoint rule over 2e5 pieces.
double travelled(double t) {
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += speed_at((i + 0.5) * t / n);
    return sum * t / n;
}

Scene ramp_channel(bool zone) {
    Scene s = test::open_channel();
    Inlet& in = s.inlets[0];
    in.velocity = {1, 0, 0};
    in.speed = speed_from_csv();
    in.profile.axis = 2;
    in.profile.points = {{0.0, 0.6}, {0.1, 1.2}};
    if (zone) {
        Outlet o;
        o.zone = true;
        o.axis = 0;
        o.upper = true;
        o.min = {0.3, s.domain.min[1], s.domain.min[2]};
        o.max = {kZoneFace, s.domain.max[1], s.domain.max[2]};
        o.pressure = kZonePressure;
        s.outlets.push_back(o);
    }
    s.validate();
    return s;
}

Options on(std::size_t devices) {
    Options o;
    o.devices = test::device_spec(devices);
    o.balance = BalanceMode::fixed;
    return o;
}

void check_unique(Simulation& sim) {
    const Particles p = sim.particles();
    std::set<std::uint32_t> ids(p.id.begin(), p.id.end());
    CHECK(ids.size() == p.size());
}

// The zone's fluid at Tait's density for its pressure, bit for bit, and none past its face.
void check_zone(Simulation& sim, const Scene& s) {
    const double c0 = s.sound_speed(), rho0 = s.physics.rho0, B = c0 * c0 * rho0 / s.physics.gamma;
    const float want = static_cast<float>(rho0 * std::pow(1.0 + kZonePressure / B, 1.0 / s.physics.gamma));
    const Particles p = sim.particles();
    std::size_t in_zone = 0, wrong = 0, past = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::fluid) continue;
        const double x = p.position[i][0];
        past += x >= kZoneFace;
        if (x < 0.3 + 1e-6 || x >= kZoneFace - 1e-6) continue;
        ++in_zone;
        wrong += p.density[i] != want;
    }
    INFO("t = " << sim.time());
    CHECK(in_zone > 50);
    CHECK(wrong == 0);
    CHECK(past == 0);
}

}  // namespace

TEST_SUITE("open_boundaries") {
TEST_CASE("a speed from a CSV file with a profile: the buffer moves by X(t + dt) - X(t), the layers are the integral's") {
    const Scene s = ramp_channel(false);
    Simulation sim(s, on(1));
    const double L = 4;  // layers in the box at the start (0.08 m at dp 0.02)
    // The section: y 0 .. 7 dp (8 points), z 0 .. 5 dp (6 columns of the profile).
    CHECK(sim.info().created == static_cast<std::size_t>(L * 8 * 6));
    std::size_t checked = 0, bad = 0;
    while (sim.time() < 0.16) {
        const double t0 = sim.time();
        const Particles before = sim.particles();
        std::map<std::uint32_t, std::size_t> at;
        for (std::size_t i = 0; i < before.size(); ++i)
            if (before.type[i] == ParticleType::fluid && before.position[i][0] < 0.08 - 2 * 0.001) at[before.id[i]] = i;
        sim.step();
        const double t1 = sim.time(), dx = travelled(t1) - travelled(t0), u1 = speed_at(t1);
        const Particles after = sim.particles();
        for (std::size_t j = 0; j < after.size(); ++j) {
            const auto it = at.find(after.id[j]);
            if (it == at.end()) continue;
            const auto& a = before.position[it->second];
            const auto& b = after.position[j];
            const double f = factor_at(a[2]);
            ++checked;
            const bool ok = std::abs((b[0] - a[0]) - f * dx) <= 1e-7 && b[1] == a[1] && b[2] == a[2] &&
                            std::abs(after.velocity[j][0] - f * u1) <= 2e-6 && after.velocity[j][1] == 0.0f && after.velocity[j][2] == 0.0f;
            if (!ok && bad++ < 8)
                FAIL_CHECK("t = " << t1 << ", particle " << after.id[j] << " at z = " << a[2] << ": moved " << b[0] - a[0] << " (want "
                                  << f * dx << "), velocity " << after.velocity[j][0] << " (want " << f * u1 << ")");
        }
        // The layers made so far: per column floor(factor X(t) / dp) beyond the L of the start.
        std::size_t want = 0;
        for (int k = 0; k <= 5; ++k) want += 8 * static_cast<std::size_t>(L + std::floor(factor_at(k * kDp) * travelled(t1) / kDp));
        if (sim.info().created != want && bad++ < 8) FAIL_CHECK("t = " << t1 << ": created " << sim.info().created << ", want " << want);
    }
    CHECK(bad == 0);
    CHECK(checked > 10000);
    MESSAGE("X(" << sim.time() << ") = " << travelled(sim.time()) << " m, " << sim.info().created << " particles made, "
                 << checked << " buffer moves checked");
}

TEST_CASE("a CSV ramp, a profile and a pressure zone on 1 and 2 devices: bitwise the same, the zone held") {
    const auto devs = test::devices();
    if (devs.size() < 2) MESSAGE("needs two devices, found " << devs.size());
    REQUIRE(devs.size() >= 2);
    const Scene s = ramp_channel(true);
    std::vector<std::unique_ptr<Simulation>> sims;
    for (std::size_t count : {1, 2}) sims.push_back(std::make_unique<Simulation>(s, on(count)));
    const std::size_t at_start = sims[0]->info().particles - sims[0]->info().created;
    for (int i = 1; i <= 300; ++i) {
        for (auto& sim : sims) {
            const StepInfo& info = sim->step();
            REQUIRE(info.particles == at_start + info.created - info.removed);
        }
        if (i % 60 != 0) continue;
        INFO("step " << i);
        check_unique(*sims[1]);
        check_zone(*sims[1], s);
        CHECK(sims[0]->info().created == sims[1]->info().created);
        CHECK(sims[0]->info().removed == sims[1]->info().removed);
        CHECK(sims[0]->time() == sims[1]->time());
        CHECK(test::differing(test::state_of(*sims[0]), test::state_of(*sims[1])) == 0);
    }
    CHECK(sims[1]->info().removed > 100);
    MESSAGE("t = " << sims[1]->time() << ": " << sims[1]->info().created << " made, " << sims[1]->info().removed << " removed past x = "
                   << kZoneFace);
}

TEST_CASE("a checkpoint in the middle of a speed ramp resumes bitwise") {
    const Scene s = ramp_channel(true);
    for (std::size_t devices : {1, 2}) {
        if (devices > test::devices().size()) continue;
        INFO(devices << " devices");
        const int N = 90, M = 90;  // t ~ 0.045 s: between the file's rows at 0.04 and 0.1 s
        Simulation straight(s, on(devices));
        for (int i = 0; i < N + M; ++i) straight.step();
        const std::string path = "open_ramps_test_" + std::to_string(devices) + ".clsph";
        {
            Simulation first(s, on(devices));
            for (int i = 0; i < N; ++i) first.step();
            CHECK(first.time() > 0.04);
            CHECK(first.time() < 0.1);
            first.save(path);
        }
        const Checkpoint c = read_checkpoint(path, &s);
        std::remove(path.c_str());
        CHECK(c.inlet_layers.size() == 6);  // a stream per lattice point of the profile
        Simulation resumed(s, c, on(devices));
        for (int i = 0; i < M; ++i) resumed.step();
        CHECK(resumed.info().created == straight.info().created);
        CHECK(resumed.info().removed == straight.info().removed);
        CHECK(resumed.info().created > c.created);
        CHECK(resumed.time() == straight.time());
        const Checkpoint x = straight.checkpoint(), y = resumed.checkpoint();
        REQUIRE(x.size() == y.size());
        CHECK(std::memcmp(x.id.data(), y.id.data(), 4 * x.size()) == 0);
        CHECK(std::memcmp(x.pos.data(), y.pos.data(), 4 * x.pos.size()) == 0);
        CHECK(std::memcmp(x.velrho.data(), y.velrho.data(), 4 * x.velrho.size()) == 0);
        CHECK(x.inlet_next_id == y.inlet_next_id);
        CHECK(x.inlet_layers == y.inlet_layers);
    }
}

TEST_CASE("an outlet zone holding a level: the fluid in it at the hydrostatic density below the level") {
    Scene s = test::small_tank(0.3, 0.1);
    Outlet o;
    o.zone = true;
    o.axis = 0;
    o.upper = true;
    o.min = {0.2, 0.0, 0.0};
    o.max = {0.3, 0.1, 0.2};
    o.level = 0.08;  // below the water's 0.1 m: the zone's water is pressed towards it
    s.outlets.push_back(o);
    s.validate();
    Simulation sim(s, on(1));
    const double c0 = s.sound_speed(), rho0 = s.physics.rho0, B = c0 * c0 * rho0 / s.physics.gamma, g = -s.physics.gravity[2];
    for (int i = 0; i < 20; ++i) sim.step();
    const Particles p = sim.particles();
    std::size_t in_zone = 0, bad = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto& x = p.position[i];
        if (p.type[i] != ParticleType::fluid || x[0] < 0.2 + 1e-6 || x[0] >= 0.3 - 1e-6 || x[2] >= 0.2 - 1e-6) continue;
        ++in_zone;
        const double want = rho0 * std::pow(1.0 + std::max(0.0, rho0 * g * (0.08 - x[2])) / B, 1.0 / s.physics.gamma);
        if (!(std::abs(p.density[i] - want) <= 2e-6 * want) && bad++ < 8)
            FAIL_CHECK("particle " << p.id[i] << " at z = " << x[2] << ": density " << p.density[i] << ", want " << want);
    }
    CHECK(bad == 0);
    CHECK(in_zone > 500);
}

TEST_CASE("the memory plan with a speed in time, a profile and outlet zones: the same capacity, their buffers as measured") {
    // The channel's inlet ramping along a profile in z, a zone holding a level and one a pressure
    // (docs/scenes.md, inlets and outlets): what fills the domain once does not depend on the speed.
    const auto path = std::filesystem::path(CLSPH_SOURCE_DIR) / "scenes" / "channel.json";
    Scene scene = load_scene(path.string(), {"physics.dp=0.02"});
    Inlet& in = scene.inlets[0];
    in.velocity = {1, 0, 0};
    in.speed.time = {0.0, 0.5};
    in.speed.value = {0.1, 0.6};
    in.profile.axis = 2;
    in.profile.points = {{0.0, 0.5}, {0.06, 1.0}};
    for (const double x : {0.6, 0.8}) {
        Outlet o;
        o.zone = true;
        o.min = {x, 0.0, 0.0};
        o.max = {x + 0.1, 0.1, 0.1};
        if (x < 0.7) o.level = 0.05; else o.pressure = 100.0;
        scene.outlets.push_back(o);
    }
    scene.validate();
    const Particles p = scene.build_particles();
    std::vector<DeviceInfo> infos;
    const auto all = list_devices();
    for (auto i : select_devices(all, std::to_string(test::devices().front()->info().index))) infos.push_back(all[i]);
    const MemoryPlan plan = plan_memory(scene, p, infos, Options{});
    CHECK(plan.planned == p.size() + 48 + 12 * 51);
    Options o;
    o.synchronous = true;
    // The open boundaries' own buffers as planned. (The cell tables are planned from the scene's
    // particles; the inlet's buffer, made at the first pass, may fill a cell more: within headroom.)
    o.devices = std::to_string(test::devices().front()->info().index);
    Simulation sim(scene, p, o);
    sim.step();
    const auto measured = sim.memory();
    const MemoryPlan again = plan_memory(scene, p, infos, o);
    REQUIRE(measured.size() == 1);
    std::map<std::string, std::size_t> predicted;
    for (const auto& b : again.devices.front().buffers) predicted[b.name] += b.bytes;
    for (const char* name : {"inlet boxes", "inlet profiles", "inlet speeds", "outlet zones"}) {
        CAPTURE(name);
        REQUIRE(measured[0].peak_buffers.count(name) == 1);
        CHECK(measured[0].peak_buffers.at(name) == predicted[name]);
    }
}
}
