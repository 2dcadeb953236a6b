// The fused step (issue 30, item 4: fewer launches a step) against the step before fusion
// (testing::Seams::unfused: a launch per stage, as before): bitwise the same particles at every
// frame and bitwise the same figures every step (time, dt, energy, speed, counts) and probes, on
// one device stepping ahead (the first kick, drift, settle, keys and the sort's first digit counts
// in one launch; the flags of the cell compaction counted by its scan; the scans' and the sort's
// tile sums added up where they are used) and on three devices (the synchronous slab path). Each run also says, from its
// profile, that it took the path it is named for, so the comparison cannot pass by both runs
// taking the same one. CTest runs this suite with POCL_DEVICES="pthread pthread pthread".
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "support/bitwise_state.hpp"
#include "support/scenes.hpp"
#include "support/skip.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace clsph;

namespace {

// The multi-device suites' dam at dp L/16 (about 7,000 particles: more than one tile of the scans
// and the sort on pocl, so their folded tile sums are taken), water sliding along the split axis
// so that particles cross the cuts, and two probes.
Scene sliding_dam() {
    Scene s = test::small_dam(0.146 / 16);
    s.fluids.front().velocity = {1.0, 0.0, 0.0};
    s.run.probe_every = 5;
    test::add_dam_probes(s);
    return s;
}

// Every step's figures as raw bits, probes on probe steps, the particles at each frame, and the
// launches by name.
struct Run {
    std::vector<std::array<double, 9>> steps;
    std::vector<double> probes;
    std::vector<test::State> frames;
    std::map<std::string, std::size_t> calls;
};

Run run(const Scene& scene, const std::string& devices, bool synchronous, bool unfused, int frames) {
    Options o;
    o.devices = devices;
    o.synchronous = synchronous;
    o.profile = true;
    // Several devices: cuts that never move. The balancer's follow measured times, which differ
    // from run to run, and with them the devices' shares of the sums (energy, probes) in their
    // last bits; the particles are bitwise the same whatever the cuts (multi_bitwise).
    o.balance = BalanceMode::off;
    testing::Seams seams;
    seams.unfused = unfused;
    testing::set_seams(o, seams);
    Simulation sim(scene, o);
    Run r;
    auto on_step = [&](const StepInfo& s) {
        r.steps.push_back({double(s.step), s.time, s.dt, double(s.particles), double(s.fluid), double(s.removed),
                           s.kinetic_energy, s.max_speed, double(s.cells)});
    };
    for (int f = 1; f <= frames; ++f) {
        sim.run_until(f * 0.0025, on_step);
        r.frames.push_back(test::state_of(sim));
        for (const auto& p : sim.sample_probes()) r.probes.push_back(p.value);
    }
    for (const auto& k : sim.profile()) r.calls[k.name] += k.calls;
    return r;
}

std::size_t calls(const Run& r, const std::string& name) {
    const auto it = r.calls.find(name);
    return it == r.calls.end() ? 0 : it->second;
}

std::size_t launches(const Run& r) {
    std::size_t n = 0;
    for (const auto& [name, c] : r.calls)
        if (name.rfind("transfer.", 0) != 0) n += c;
    return n;
}

void check_same(const Run& fused, const Run& unfused) {
    REQUIRE(unfused.steps.size() > 20);
    REQUIRE(fused.steps.size() == unfused.steps.size());
    for (std::size_t i = 0; i < fused.steps.size(); ++i) {
        for (std::size_t k = 0; k < fused.steps[i].size(); ++k) {
            INFO("step " << unfused.steps[i][0] << ", figure " << k << ": " << fused.steps[i][k] << " against "
                         << unfused.steps[i][k]);
            CHECK(std::memcmp(&fused.steps[i][k], &unfused.steps[i][k], sizeof(double)) == 0);
        }
    }
    REQUIRE(unfused.probes.size() >= 4);
    REQUIRE(fused.probes.size() == unfused.probes.size());
    CHECK(std::memcmp(fused.probes.data(), unfused.probes.data(), fused.probes.size() * sizeof(double)) == 0);
    REQUIRE(fused.frames.size() == unfused.frames.size());
    for (std::size_t f = 0; f < fused.frames.size(); ++f) {
        INFO("frame " << f + 1);
        CHECK(fused.frames[f].size() > 1000);
        CHECK(test::differing(fused.frames[f], unfused.frames[f]) == 0);
    }
    MESSAGE("launches: " << launches(unfused) << " unfused, " << launches(fused) << " fused, in "
                         << unfused.steps.size() << " steps");
    CHECK(launches(fused) < launches(unfused));
    // The compaction's flags: a launch of their own only unfused.
    CHECK(calls(fused, "cells.flag") == 0);
    CHECK(calls(unfused, "cells.flag") >= unfused.steps.size());
}

}  // namespace

TEST_SUITE("fused_step") {
TEST_CASE("one device stepping ahead: the fused step is bitwise the unfused one (frames, figures, probes)") {
    const auto devs = test::devices();
    REQUIRE(!devs.empty());
    const std::string one = test::device_spec(1);
    const Scene scene = sliding_dam();
    const Run unfused = run(scene, one, false, true, 4);
    const Run fused = run(scene, one, false, false, 4);
    if (calls(unfused, "clock.end") == 0) {  // no cl_khr_fp64: no step ahead on this device
        test_skip::skip("the step ahead needs cl_khr_fp64, which device " + one + " lacks");
        return;
    }
    check_same(fused, unfused);
    // Drift, settle and keys: one launch a step fused, three unfused.
    CHECK(calls(fused, "cells.drift_keys") >= fused.steps.size());
    CHECK(calls(fused, "sph.kick_drift") == 0);
    CHECK(calls(unfused, "cells.drift_keys") == 0);
    CHECK(calls(unfused, "sph.kick_drift") >= unfused.steps.size());
    // The sort's first histogram in that launch too.
    CHECK(calls(fused, "sort.histogram") + fused.steps.size() <= calls(unfused, "sort.histogram"));
    // More than one tile: the folded sums were taken (no scan of the sort's digit counts).
    CHECK(calls(fused, "sort.scan.tiles") == 0);
    CHECK(calls(unfused, "sort.scan.tiles") > 0);
}

TEST_CASE("three devices: the fused step is bitwise the unfused one (frames, figures, probes)") {
    const auto devs = test::devices();
    if (devs.size() < 3) {
        test_skip::skip("needs three devices of one implementation, found " + std::to_string(devs.size()));
        return;
    }
    const std::string three = test::device_spec(3);
    const Scene scene = sliding_dam();
    const Run unfused = run(scene, three, true, true, 3);
    const Run fused = run(scene, three, true, false, 3);
    check_same(fused, unfused);
}
}
