// Checkpoints (docs/checkpoint.md): N + M steps straight against N steps, a checkpoint written and
// read back into a new Simulation, M steps — bitwise the same particle arrays and step counters, on
// one device (suite checkpoint) and on three devices of one implementation (checkpoint_multi; CTest
// runs it with POCL_DEVICES="pthread pthread pthread"); onto another device count, the same
// particles within round-off; corrupt, truncated and foreign files refused by name.
#include "clsph/checkpoint.hpp"
#include "clsph/simulation.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

using namespace clsph;

namespace {

Scene sliding_dam() {
    Scene s = test::small_dam(0.146 / 8);
    s.fluids.front().velocity = {2.0, 0.0, 0.0};
    return s;
}

std::string temp_path(const std::string& name) { return "checkpoint_test_" + name + ".clsph"; }

// Particles by id: position (double), velocity, density — as raw bytes.
std::map<std::uint32_t, std::array<double, 7>> by_id(Simulation& sim) {
    const Particles p = sim.particles();
    std::map<std::uint32_t, std::array<double, 7>> m;
    for (std::size_t i = 0; i < p.size(); ++i)
        m[p.id[i]] = {p.position[i][0], p.position[i][1], p.position[i][2], p.velocity[i][0], p.velocity[i][1],
                      p.velocity[i][2], p.density[i]};
    return m;
}

// With the dynamic balance the cuts follow measured times, so two straight runs already cut
// differently: the particle arrays are bitwise the same, the sums over devices (kinetic energy)
// only to round-off. With static cuts, the checkpoint's cuts are restored and every row is exact.
void check_restart_bitwise(std::size_t devices, bool synchronous, BalanceMode balance = BalanceMode::fixed,
                           Viscosity viscosity = Viscosity::artificial, WallSlip slip = WallSlip::wall) {
    const bool exact_rows = devices == 1 || balance != BalanceMode::dynamic;
    Scene scene = sliding_dam();
    scene.physics.viscosity = viscosity;
    if (slip == WallSlip::no_slip) {
        // At 2 m/s the walls mirror the block's impulsive start (a floor sliding back under it at
        // 2 m/s, a wall behind it receding), and a boundary density extrapolated from its ghost node
        // leaves the 1.3 rho0 band by step 48: 1 m/s, as the mDBC bitwise suite.
        scene.boundary_method = BoundaryMethod::mdbc;
        scene.wall_slip = slip;
        scene.physics.kinematic_viscosity = 1e-4;
        scene.fluids.front().velocity = {1.0, 0.0, 0.0};
    }
    Options o;
    o.devices = test::device_spec(devices);
    o.synchronous = synchronous;
    o.balance = balance;
    const int N = 30, M = 40;
    Simulation straight(scene, o);
    for (int i = 0; i < N + M; ++i) straight.step();

    const std::string path = temp_path("bitwise" + std::to_string(devices));
    std::vector<StepInfo> rows;
    {
        Simulation first(scene, o);
        for (int i = 0; i < N; ++i) first.step();
        first.save(path);
    }
    const Checkpoint c = read_checkpoint(path, &scene);
    CHECK(c.step == N);
    CHECK(c.counts.size() == devices);
    Simulation resumed(scene, c, o);
    CHECK(resumed.info().step == N);
    for (int i = 0; i < M; ++i) resumed.step();
    std::remove(path.c_str());

    const auto& a = straight.info();
    const auto& b = resumed.info();
    CHECK(a.step == b.step);
    CHECK(a.time == b.time);  // exact: every dt came out the same
    CHECK(a.dt == b.dt);
    if (exact_rows) CHECK(a.kinetic_energy == b.kinetic_energy);
    else CHECK(std::abs(a.kinetic_energy - b.kinetic_energy) <= 1e-5 * a.kinetic_energy);
    CHECK(a.max_speed == b.max_speed);
    CHECK(a.particles == b.particles);
    // The raw arrays of the next step's input, in the devices' order.
    const Checkpoint x = straight.checkpoint(), y = resumed.checkpoint();
    REQUIRE(x.size() == y.size());
    if (exact_rows) CHECK(x.counts == y.counts);
    CHECK(std::memcmp(x.id.data(), y.id.data(), 4 * x.size()) == 0);
    CHECK(std::memcmp(x.pos.data(), y.pos.data(), 4 * x.pos.size()) == 0);
    CHECK(std::memcmp(x.velrho.data(), y.velrho.data(), 4 * x.velrho.size()) == 0);
    CHECK(std::memcmp(x.accel.data(), y.accel.data(), 4 * x.accel.size()) == 0);
    CHECK(x.dt_next == y.dt_next);
}

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void spit(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
std::string refusal(const std::string& path, const Scene& scene) {
    try {
        read_checkpoint(path, &scene);
    } catch (const CheckpointError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_SUITE("checkpoint") {
TEST_CASE("N + M steps straight == N steps, checkpoint, read back, M steps (one device)") {
    check_restart_bitwise(1, true);
}

TEST_CASE("the same from the step ahead (one device with fp64)") {
    check_restart_bitwise(1, false);
}

TEST_CASE("laminar+sps: resumed bitwise, synchronous and from the step ahead (the stress is not stored)") {
    check_restart_bitwise(1, true, BalanceMode::fixed, Viscosity::laminar_sps);
    check_restart_bitwise(1, false, BalanceMode::fixed, Viscosity::laminar_sps);
}

TEST_CASE("mDBC no-slip walls: resumed bitwise (their mirrored velocities travel in the accelerations)") {
    check_restart_bitwise(1, true, BalanceMode::fixed, Viscosity::laminar, WallSlip::no_slip);
    check_restart_bitwise(1, false, BalanceMode::fixed, Viscosity::laminar, WallSlip::no_slip);
}

TEST_CASE("a flipped byte, a truncated file, another scene's checkpoint: refused naming file and reason") {
    const Scene scene = sliding_dam();
    Options o;
    o.devices = test::device_spec(1);
    const std::string path = temp_path("refused");
    {
        Simulation sim(scene, o);
        for (int i = 0; i < 5; ++i) sim.step();
        sim.save(path);
    }
    const std::string good = slurp(path);
    CHECK(refusal(path, scene).empty());

    std::string flipped = good;
    flipped[flipped.size() / 2] ^= 0x10;
    spit(path, flipped);
    auto msg = refusal(path, scene);
    CHECK(msg.find(path) != std::string::npos);
    CHECK(msg.find("checksum") != std::string::npos);

    spit(path, good.substr(0, good.size() - 100));
    msg = refusal(path, scene);
    CHECK(msg.find(path) != std::string::npos);
    CHECK(msg.find("truncated") != std::string::npos);

    spit(path, good);
    Scene other = scene;
    other.physics.coefsound = 20;
    msg = refusal(path, other);
    CHECK(msg.find(path) != std::string::npos);
    CHECK(msg.find("another scene") != std::string::npos);

    std::string newer = good;
    newer[8] = 7;  // the format version
    spit(path, newer);
    msg = refusal(path, scene);
    CHECK(msg.find("format version 7") != std::string::npos);
    std::remove(path.c_str());
}
}

TEST_SUITE("checkpoint_multi") {
TEST_CASE("N + M straight == N, checkpoint, read back, M on three devices of one implementation") {
    const auto devs = test::devices();
    if (devs.size() < 3) MESSAGE("needs three devices of one implementation, found " << devs.size());
    REQUIRE(devs.size() >= 3);
    check_restart_bitwise(3, true, BalanceMode::fixed);
    check_restart_bitwise(3, true, BalanceMode::dynamic);
    check_restart_bitwise(3, true, BalanceMode::fixed, Viscosity::laminar_sps);  // two halo columns
}

TEST_CASE("a checkpoint of three devices resumed on one: the same particles, positions within round-off") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 3);
    const Scene scene = sliding_dam();
    Options three, one;
    three.devices = test::device_spec(3);
    one.devices = test::device_spec(1);
    const std::string path = temp_path("moved");
    Simulation straight(scene, three);
    for (int i = 0; i < 20; ++i) straight.step();
    straight.save(path);
    const Checkpoint c = read_checkpoint(path, &scene);
    std::remove(path.c_str());
    Simulation moved(scene, c, one);
    for (int i = 0; i < 10; ++i) {
        straight.step();
        moved.step();
    }
    const auto a = by_id(straight), b = by_id(moved);
    REQUIRE(a.size() == b.size());
    double worst = 0;
    for (const auto& [id, x] : a) {
        const auto it = b.find(id);
        REQUIRE(it != b.end());
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(x[k] - it->second[k]));
    }
    CHECK(worst < 1e-5 * 0.146);
}
}
