// The step ahead (docs/multi_device.md): dt chosen on the device, the cell tables over a bound,
// the statistics read a few steps behind. Against the synchronous path (Options::synchronous) on
// one pocl device (the step ahead needs cl_khr_fp64): the same steps at the same times, frames and
// probes where they were, bitwise the same particles, the same failure, and the same results when
// the number of non-empty cells outgrows the bound.
#include "clsph/devices.hpp"
#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "support/bitwise_state.hpp"
#include "support/scenes.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace clsph;

namespace {

// One pocl device (the threaded one where there is one): the step ahead runs on one device.
std::string one_pocl_device() {
    std::string pick;
    for (const auto& d : list_devices()) {
        if (d.platform.find("Portable") == std::string::npos) continue;
        if (pick.empty() || d.name.rfind("pthread", 0) == 0) pick = std::to_string(d.index);
    }
    REQUIRE_MESSAGE(!pick.empty(), "no pocl device");
    return pick;
}

// pocl devices (they have cl_khr_fp64, which the step ahead needs) whose name starts with `kind`
// ("": every one), as a --devices spec.
std::string pocl_devices(const std::string& kind, std::size_t* count) {
    std::string spec;
    std::size_t n = 0;
    for (const auto& d : list_devices())
        if (d.platform.find("Portable") != std::string::npos && d.fp64 && d.name.rfind(kind, 0) == 0)
            spec += (n++ ? "," : "") + std::to_string(d.index);
    *count = n;
    return spec;
}

Options options(bool synchronous) {
    Options o;
    o.devices = one_pocl_device();
    o.synchronous = synchronous;
    return o;
}

std::unique_ptr<Simulation> make(const Scene& scene, const Options& o) {
    auto sim = std::make_unique<Simulation>(scene, o);
    REQUIRE(sim->device_names().size() >= 1);
    return sim;
}

using test::differing;
using test::State;
using test::state_of;

Scene probed_dam() {
    Scene s = test::dam_break_slice(0.146, 0.146 / 14, 3.0, x_min | x_max | z_min);
    s.physics.coefsound = 10;
    s.run.probe_every = 7;
    test::add_dam_probes(s);
    return s;
}

// What the clsph tool's loop sees: every step (number, time and dt as bits), probes on probe
// steps, and a frame (time and state) at every multiple of `every` up to `until`.
struct Run {
    std::vector<std::array<double, 3>> steps;
    std::vector<double> probes;
    std::vector<double> frame_times;
    std::vector<State> frames;
};

Run run(Simulation& sim, double every, double until) {
    Run r;
    auto on_step = [&](const StepInfo& s) {
        r.steps.push_back({static_cast<double>(s.step), s.time, s.dt});
        if (s.step % 7 == 0)
            for (const auto& p : sim.sample_probes()) r.probes.push_back(p.value);
    };
    for (int f = 1; sim.time() < until - 1e-12; ++f) {
        sim.run_until(std::min(f * every, until), on_step);
        r.frame_times.push_back(sim.time());
        r.frames.push_back(state_of(sim));
    }
    return r;
}

}  // namespace

TEST_SUITE("step_ahead") {
TEST_CASE("frames, probes and --until land where the synchronous path puts them, with bitwise the same particles") {
    const Scene scene = probed_dam();
    auto sync = make(scene, options(true));
    auto ahead = make(scene, options(false));
    CHECK_FALSE(sync->steps_ahead());
    REQUIRE(ahead->steps_ahead());
    const double every = 0.004, until = 0.0173;  // the last frame off the frame grid
    const Run a = run(*sync, every, until), b = run(*ahead, every, until);
    REQUIRE(a.steps.size() > 60);
    REQUIRE(a.steps.size() == b.steps.size());
    for (std::size_t i = 0; i < a.steps.size(); ++i) {
        INFO("step " << a.steps[i][0]);
        CHECK(std::memcmp(a.steps[i].data(), b.steps[i].data(), sizeof a.steps[i]) == 0);
    }
    REQUIRE(a.frame_times.size() == 5);
    CHECK(a.frame_times == b.frame_times);
    CHECK(a.frame_times.back() == doctest::Approx(until).epsilon(1e-12));
    CHECK(a.frame_times[0] == doctest::Approx(every).epsilon(1e-12));
    REQUIRE(a.probes.size() > 10);
    REQUIRE(a.probes.size() == b.probes.size());
    CHECK(std::memcmp(a.probes.data(), b.probes.data(), a.probes.size() * sizeof(double)) == 0);
    for (std::size_t f = 0; f < a.frames.size(); ++f) CHECK(differing(a.frames[f], b.frames[f]) == 0);
    CHECK(sync->info().step == ahead->info().step);
}

TEST_CASE("a blow-up found steps later names the same step, time and particle, with the same last good state") {
    // Water thrown at the wall faster than the sound speed allows: a density leaves the band.
    Scene scene = test::dam_break_slice(0.146, 0.146 / 12, 3.0, x_min | x_max | z_min);
    scene.physics.coefsound = 10;
    scene.physics.density_max = 1.03;
    scene.fluids.front().velocity = {-0.25, 0.0, 0.0};
    std::string messages[2];
    std::vector<std::array<double, 3>> steps[2];
    State last_good[2];
    for (int k = 0; k < 2; ++k) {
        auto sim = make(scene, options(k == 0));
        CHECK(sim->steps_ahead() == (k == 1));
        try {
            for (int f = 1; f < 100; ++f) {
                sim->run_until(f * 0.002, [&](const StepInfo& s) { steps[k].push_back({double(s.step), s.time, s.dt}); });
                sim->particles();  // a frame: the last good state
            }
        } catch (const SimulationError& e) {
            messages[k] = e.what();
        }
        last_good[k] = state_of(sim->last_good());
    }
    INFO(messages[0]);
    REQUIRE(messages[0].find("outside the allowed band") != std::string::npos);
    CHECK(messages[1] == messages[0]);
    CHECK(steps[1] == steps[0]);
    REQUIRE(steps[0].size() > 12);  // found after a frame or more
    CHECK(last_good[0].size() > 100);
    CHECK(differing(last_good[0], last_good[1]) == 0);
}

TEST_CASE("cells outgrowing the tables' bound: the step is redone, with the same result as a generous bound") {
    // A block of soft water in free fall, released from its hydrostatic pressure: it spreads out
    // in every direction, and the non-empty cells grow past the bound the first tables were
    // given with no headroom (their count plus 16).
    Scene scene = test::dam_break_slice(0.146, 0.146 / 12, 3.0, 0);
    scene.walls.clear();  // no faces: no walls (a wall with no faces is a scene error)
    scene.physics.coefsound = 2;
    scene.fluids.front().min = {0.1, 0, 0.1};
    scene.fluids.front().max = {0.3, scene.fluids.front().max[1], 0.3};
    Options tight = options(false), generous = options(false);
    tight.cell_headroom = 0.0;
    generous.cell_headroom = 4.0;
    auto a = make(scene, tight), b = make(scene, generous);
    REQUIRE(a->steps_ahead());
    const std::size_t first_cells = a->info().cells;
    REQUIRE(first_cells > 0);
    a->run_until(0.1);
    b->run_until(0.1);
    INFO("cells: " << first_cells << " at the start, " << a->info().cells << " at the end");
    CHECK(a->info().cells > first_cells + 16);  // past the first bound
    CHECK(a->info().step == b->info().step);
    CHECK(a->info().time == b->info().time);
    CHECK(differing(state_of(*a), state_of(*b)) == 0);
    // And the synchronous path, whose tables follow the count exactly, agrees with both.
    auto c = make(scene, options(true));
    c->run_until(0.1);
    CHECK(differing(state_of(*a), state_of(*c)) == 0);
}
}

TEST_SUITE("step_ahead") {
TEST_CASE("particles leaving the domain while steps are in flight: removed at the same steps, the same states") {
    // Water thrown at a floor with open ends: the splash leaves the domain at both ends.
    Scene scene = test::dam_break_slice(0.146, 0.146 / 12, 3.0, z_min);
    scene.physics.coefsound = 10;
    scene.fluids.front().min = {0.15, 0, 0.03};
    scene.fluids.front().max = {0.29, scene.fluids.front().max[1], 0.13};
    scene.fluids.front().velocity = {0.0, 0.0, -2.5};
    std::vector<std::array<std::size_t, 3>> counts[2];  // step, particles, removed
    State states[2];
    for (int k = 0; k < 2; ++k) {
        auto sim = make(scene, options(k == 0));
        CHECK(sim->steps_ahead() == (k == 1));
        for (int f = 1; f <= 4; ++f)
            sim->run_until(f * 0.02, [&](const StepInfo& s) { counts[k].push_back({s.step, s.particles, s.removed}); });
        states[k] = state_of(*sim);
    }
    REQUIRE(counts[0].size() > 100);
    CHECK(counts[0].back()[2] > 100);  // many left
    CHECK(counts[0].back()[1] + counts[0].back()[2] == counts[0].front()[1] + counts[0].front()[2]);
    CHECK(counts[1] == counts[0]);
    CHECK(states[0].size() == counts[0].back()[1]);
    CHECK(differing(states[0], states[1]) == 0);
}
}

TEST_SUITE("step_ahead") {
TEST_CASE("a collapsing time step stops both paths at the same step with the same error") {
    // dt_collapse 0.97: the CFL step falls below 0.97 of the acoustic step at rest as soon as
    // the fastest particle passes 3 % of c0, some steps into the collapse of the column.
    Scene scene = probed_dam();
    std::string messages[2];
    std::uint64_t steps[2] = {0, 0};
    State states[2];
    for (int k = 0; k < 2; ++k) {
        Options o = options(k == 0);
        o.dt_collapse = 0.97;
        auto sim = make(scene, o);
        try {
            sim->run_until(0.05, [&](const StepInfo& s) { steps[k] = s.step; });
        } catch (const SimulationError& e) {
            messages[k] = e.what();
        }
        states[k] = state_of(*sim);  // the steps in flight after it changed nothing
    }
    CHECK(differing(states[0], states[1]) == 0);
    INFO(messages[0]);
    REQUIRE(messages[0].find("the time step collapsed") != std::string::npos);
    CHECK(steps[0] > 5);
    CHECK(messages[1] == messages[0]);
    CHECK(steps[1] == steps[0]);
}
}

TEST_SUITE("step_ahead") {
TEST_CASE("--steps: with a step limit the callback that stops the run finds no step past it in flight") {
    const Scene scene = probed_dam();
    State states[2];
    std::uint64_t steps[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        Options o = options(k == 0);
        o.step_limit = 45;
        auto sim = make(scene, o);
        struct Stop {};
        try {
            sim->run_until(1.0, [&](const StepInfo& s) {
                if (s.step >= 45) throw Stop{};  // what the clsph tool's --steps does
            });
        } catch (const Stop&) {
        }
        steps[k] = sim->info().step;
        states[k] = state_of(*sim);
    }
    CHECK(steps[0] == 45);
    CHECK(steps[1] == 45);
    CHECK(differing(states[0], states[1]) == 0);
}

// The step ahead on several devices (docs/multi_device.md): with the cell tables kept, every device
// takes the step its clock chose from every device's reductions (copied device to device), the
// ghosts come from their owners without the host, and a step that must build the tables halts
// them all and is taken synchronously. Against the synchronous path on one device: the same steps,
// builds, probes, frames and particles. On the pocl devices there are (separate contexts: the copies
// staged through the host by the relay's thread) and on one device opened as three slabs (one
// context: copies on the devices' queues).
TEST_CASE("tables kept over steps: steps ahead on several devices and slabs take the synchronous steps, builds and particles bitwise") {
    Scene scene = probed_dam();
    scene.run.list_buffer = 0.1;  // half of it is a few steps' travel as the water falls: builds all along
    // The period 10 dp instead of 8: three cells of a support and the buffer.
    const double dp = scene.physics.dp;
    scene.domain.max[1] = 10 * dp;
    scene.walls.front().max[1] = 9 * dp;
    scene.fluids.front().max[1] = 9.5 * dp;
    scene.domain.split_axis = 0;
    auto sync = make(scene, options(true));
    CHECK_FALSE(sync->steps_ahead());
    const double every = 0.004, until = 0.0173;
    const Run want = run(*sync, every, until);
    const TableBuilds want_builds = sync->table_builds();
    MESSAGE(want_builds.builds << " builds in " << want.steps.size() << " steps");
    REQUIRE(want_builds.builds > 3);                        // rebuilt when due ...
    REQUIRE(want_builds.builds < want.steps.size() / 2);   // ... and kept in between
    // ahead: whether the steps run ahead (pocl's basic device keeps several devices synchronous:
    // cl/quirks.hpp user_events_stop), with the same results either way.
    struct Case { std::string name, devices; std::size_t slabs; bool ahead; };
    std::vector<Case> cases = {{"one device", one_pocl_device(), 1, true},
                               {"three slabs of one device", one_pocl_device(), 3, true}};
    std::size_t threaded = 0, all = 0;
    const std::string threaded_spec = pocl_devices("pthread", &threaded), all_spec = pocl_devices("", &all);
    if (threaded >= 2) cases.push_back({std::to_string(threaded) + " pthread devices", threaded_spec, 1, true});
    else MESSAGE("fewer than two pthread devices: the copies across contexts are tested in multi_bitwise");
    if (all > threaded && all >= 2) cases.push_back({"every pocl device, a basic one among them", all_spec, 1, false});
    for (const auto& c : cases) {
        CAPTURE(c.name);
        Options o = options(false);
        o.devices = c.devices;
        o.balance = BalanceMode::fixed;  // the same cuts in both runs (the probes depend on them, below)
        if (c.slabs > 1) {
            testing::Seams seams;
            seams.slabs = c.slabs;
            testing::set_seams(o, seams);
        }
        auto ahead = make(scene, o);
        REQUIRE(ahead->steps_ahead() == c.ahead);
        const Run got = run(*ahead, every, until);
        // Probes near a cut read the ghosts as copied after the drift (before the kick), so on
        // several slabs they differ from one device's in the last bits, and with the cuts: against
        // the synchronous run on the same slabs and cuts.
        o.synchronous = true;
        auto same_slabs = make(scene, o);
        const Run sync_probes = run(*same_slabs, every, until);
        REQUIRE(got.steps.size() == want.steps.size());
        std::size_t differ = 0;
        for (std::size_t i = 0; i < want.steps.size(); ++i)
            differ += std::memcmp(want.steps[i].data(), got.steps[i].data(), sizeof want.steps[i]) != 0;
        CHECK(differ == 0);
        CHECK(ahead->table_builds().builds == want_builds.builds);
        CHECK(ahead->table_builds().age == want_builds.age);
        // The host foresees the builds (ListSchedule::likely_kept): steps in flight behind a halted
        // one, computed for nothing, are the exception (before: up to Options::steps_ahead - 1 a build).
        MESSAGE(c.name << ": " << ahead->steps_taken_ahead() << " steps taken ahead, " << ahead->steps_thrown_ahead()
                       << " thrown away, " << want_builds.builds << " builds");
        if (c.ahead) CHECK(ahead->steps_taken_ahead() + want_builds.builds - 1 == want.steps.size());
        CHECK(ahead->steps_thrown_ahead() * 4 < want_builds.builds);
        CHECK(got.frame_times == want.frame_times);
        REQUIRE(got.probes.size() == sync_probes.probes.size());
        CHECK(std::memcmp(got.probes.data(), sync_probes.probes.data(), got.probes.size() * sizeof(double)) == 0);
        REQUIRE(got.frames.size() == want.frames.size());
        for (std::size_t f = 0; f < want.frames.size(); ++f) CHECK(differing(want.frames[f], got.frames[f]) == 0);
    }
}
}

TEST_SUITE("step_ahead") {
TEST_CASE("step() after run_until: the synchronous steps run on devices the steps ahead left halted") {
    // run_until stops the steps ahead at its time (every device halts past it) or before a build of
    // the kept tables (halted for it): the synchronous step() after it must still move the particles.
    for (const double buffer : {0.0, 0.1}) {
        CAPTURE(buffer);
        Scene scene = probed_dam();
        scene.run.list_buffer = buffer;
        const double dp = scene.physics.dp;  // the period 10 dp: three cells of a support and the buffer
        scene.domain.max[1] = 10 * dp;
        scene.walls.front().max[1] = 9 * dp;
        scene.fluids.front().max[1] = 9.5 * dp;
        State states[2];
        std::uint64_t steps[2] = {0, 0};
        for (int k = 0; k < 2; ++k) {
            auto sim = make(scene, options(k == 0));
            CHECK(sim->steps_ahead() == (k == 1));
            for (int round = 0; round < 3; ++round) {
                sim->run_until(0.004 * (round + 1));
                for (int i = 0; i < 4; ++i) sim->step();
            }
            steps[k] = sim->info().step;
            states[k] = state_of(*sim);
        }
        CHECK(steps[1] == steps[0]);
        CHECK(differing(states[0], states[1]) == 0);
    }
}
}
