// One simulation across MPI ranks (issue 21), run by mpiexec with N = 2 and 3 ranks on one machine,
// each rank driving one device (CTest gives POCL_DEVICES="pthread" N times: the node's devices dealt
// one to each rank). The same scene then runs in one process on the N devices (rank 0, while the
// others wait), and the two runs must leave the same particles, bit for bit: the exchange takes
// arrivals in the same order wherever the slabs run, and the reductions (time step, counts) are exact.
// A checkpoint taken across the ranks holds every slab in slab order on rank 0 only (the same file
// as one process writes when the cuts are the same; the other ranks' hold no particles), and a run
// restarted from it across the ranks goes on bitwise.
// A moving solid (issue 32) crosses the rank boundary the same way, as do an inlet's new particles,
// and a floating box's state (summed over the ranks) is the same on every rank and as in one process,
// checkpoint included.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "clsph/checkpoint.hpp"
#include "clsph/error.hpp"
#include "clsph/ranks.hpp"
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "support/bitwise_state.hpp"
#include "support/cut_schedules.hpp"
#include "support/scenes.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <thread>
#include <vector>

using namespace clsph;

namespace {

std::shared_ptr<Ranks> ranks;

// Particles by id: position (as decoded, double), velocity and density.
using State = std::map<std::uint32_t, std::array<double, 7>>;

// Waits for every rank without spinning a core (the devices' threads need both cores).
void gentle_barrier() {
    MPI_Request r;
    MPI_Ibarrier(MPI_COMM_WORLD, &r);
    for (int done = 0; !done;) {
        MPI_Test(&r, &done, MPI_STATUS_IGNORE);
        if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

std::array<double, 7> words(const Particles& p, std::size_t i) {
    return {p.position[i][0], p.position[i][1], p.position[i][2], p.velocity[i][0], p.velocity[i][1], p.velocity[i][2],
            p.density[i]};
}

// Every rank's particles, on every rank; `duplicates` counts ids seen twice.
State gather_state(Simulation& sim, std::size_t& duplicates) {
    const Particles p = sim.particles();
    std::vector<double> mine;  // id (exact in a double), then the 7 words
    for (std::size_t i = 0; i < p.size(); ++i) {
        mine.push_back(p.id[i]);
        for (double x : words(p, i)) mine.push_back(x);
    }
    int n = static_cast<int>(mine.size()), size = ranks_in(*ranks);
    std::vector<int> counts(static_cast<std::size_t>(size)), at(static_cast<std::size_t>(size), 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (int r = 1; r < size; ++r) at[static_cast<std::size_t>(r)] = at[static_cast<std::size_t>(r) - 1] + counts[static_cast<std::size_t>(r) - 1];
    std::vector<double> all(static_cast<std::size_t>(at.back() + counts.back()));
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), at.data(), MPI_DOUBLE, MPI_COMM_WORLD);
    State s;
    duplicates = 0;
    for (std::size_t i = 0; i + 8 <= all.size(); i += 8) {
        std::array<double, 7> w;
        std::copy(all.begin() + static_cast<std::ptrdiff_t>(i) + 1, all.begin() + static_cast<std::ptrdiff_t>(i) + 8, w.begin());
        duplicates += !s.emplace(static_cast<std::uint32_t>(all[i]), w).second;
    }
    return s;
}

State local_state(Simulation& sim) {
    const Particles p = sim.particles();
    State s;
    for (std::size_t i = 0; i < p.size(); ++i) s[p.id[i]] = words(p, i);
    return s;
}

long differing(const State& a, const State& b) {
    if (a.size() != b.size()) return -1;
    long n = 0;
    for (const auto& [id, w] : a) {
        const auto it = b.find(id);
        if (it == b.end()) return -1;
        const bool differs = std::memcmp(w.data(), it->second.data(), sizeof w) != 0;
        if (differs && n < 3) {  // the first few, word by word (position, velocity, density)
            std::string words;
            for (std::size_t k = 0; k < w.size(); ++k)
                if (std::memcmp(&w[k], &it->second[k], sizeof(double)) != 0)
                    words += " [" + std::to_string(k) + "] " + std::to_string(w[k]) + " vs " + std::to_string(it->second[k]);
            MESSAGE("particle " << id << " differs:" << words);
        }
        n += differs;
    }
    return n;
}

// Every rank's floating bodies the same as rank 0's (bit for bit: their doubles as bytes).
bool bodies_agree(const std::vector<BodySample>& mine) {
    std::vector<double> w;
    for (const auto& b : mine) {
        w.insert(w.end(), b.position.begin(), b.position.end());
        w.insert(w.end(), b.quaternion.begin(), b.quaternion.end());
        w.insert(w.end(), b.velocity.begin(), b.velocity.end());
        w.insert(w.end(), b.angular_velocity.begin(), b.angular_velocity.end());
        w.insert(w.end(), b.force.begin(), b.force.end());
        w.insert(w.end(), b.torque.begin(), b.torque.end());
    }
    std::vector<double> first = w;
    MPI_Bcast(first.data(), static_cast<int>(first.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    int same = std::memcmp(first.data(), w.data(), sizeof(double) * w.size()) == 0 ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return same == 1;
}

// The scene on N ranks, then in one process on the node's N devices (rank 0), `steps` steps each.
// Floating bodies: their states the same on every rank and as in one process, in the checkpoint
// too, and after the restart.
// With `same_cuts` (the cuts forced alike), their checkpoints must be the same too, array for array.
// `split`, if given, gets this rank's force passes split around the halo.
void compare(const Scene& scene, int steps, const std::function<void(Options&)>& adjust, bool same_cuts = false,
             std::size_t* split = nullptr) {
    const int rank = rank_of(*ranks);
    Options o;
    adjust(o);
    o.ranks = ranks;
    Simulation across(scene, o);
    for (int i = 0; i < steps; ++i) across.step();
    // One slab here, the other on the other rank, and particles came across the rank boundary.
    const auto shares = across.shares();
    if (split) *split = shares.empty() ? 0 : shares[0].split_force_passes;
    REQUIRE(shares.size() == 1);
    CHECK(shares[0].received_bytes > 0);
    CHECK(shares[0].particles < across.info().particles);
    // The dynamic balancer's calibration before the first step ran across the ranks: this rank
    // timed its own device (the bitwise comparison below holds whatever cuts it chose).
    if (o.balance == BalanceMode::dynamic) CHECK(shares[0].calibrated_whole_scene_seconds > 0);
    std::size_t duplicates = 0;
    const State spread = gather_state(across, duplicates);
    CHECK(duplicates == 0);
    CHECK(spread.size() == across.info().particles);
    const Checkpoint saved = across.checkpoint();  // every rank's slabs, on rank 0 only
    CHECK(saved.size() == (rank == 0 ? across.info().particles : 0));
    if (scene.has_floating()) {
        CHECK(bodies_agree(across.bodies()));
        CHECK(saved.bodies.size() == across.bodies().size() * 44u);  // BodyState::kDoubles, on every rank
    }
    if (rank == 0) {
        Options one;
        adjust(one);
        one.devices.clear();  // the node's devices, one per rank
        for (int r = 0; r < ranks_in(*ranks); ++r) one.devices += (r ? "," : "") + std::to_string(r);
        Simulation sim(scene, one);
        for (int i = 0; i < steps; ++i) sim.step();
        CHECK(sim.time() == across.time());  // dt from exact reductions
        CHECK(sim.info().fluid == across.info().fluid);
        const long d = differing(local_state(sim), spread);
        INFO("particles differing in any bit (-1: the ids differ): " << d);
        CHECK(d == 0);
        CHECK(test::same_bodies(sim.bodies(), across.bodies()));
        if (scene.has_floating()) CHECK(sim.checkpoint().bodies == saved.bodies);
        if (same_cuts) {
            const Checkpoint one_saved = sim.checkpoint();
            CHECK(one_saved.counts == saved.counts);
            CHECK(one_saved.cuts == saved.cuts);
            CHECK(one_saved.id == saved.id);
            CHECK(std::memcmp(one_saved.pos.data(), saved.pos.data(), 4 * saved.pos.size()) == 0);
            CHECK(std::memcmp(one_saved.velrho.data(), saved.velrho.data(), 4 * saved.velrho.size()) == 0);
            CHECK(std::memcmp(one_saved.accel.data(), saved.accel.data(), 4 * saved.accel.size()) == 0);
        }
    }
    // Restarted across the ranks from that checkpoint (rank 0's file, read by every rank as
    // `clsph resume` does), 20 more steps: bitwise the run that went on.
    const std::string path = "mpi_run_checkpoint_" + std::to_string(ranks_in(*ranks)) + ".clsph";  // mpi_run, mpi_run_3
    if (rank == 0) write_checkpoint(path, saved);
    gentle_barrier();
    const Checkpoint file = read_checkpoint(path, &scene);
    CHECK(file.size() == across.info().particles);
    Simulation again(scene, file, o);
    std::size_t dup_again = 0;
    CHECK(differing(gather_state(again, dup_again), spread) == 0);
    for (int i = 0; i < 20; ++i) {
        across.step();
        again.step();
    }
    CHECK(again.time() == across.time());
    CHECK(test::same_bodies(again.bodies(), across.bodies()));
    std::size_t dup_on = 0;
    const long restarted = differing(gather_state(again, dup_again), gather_state(across, dup_on));
    INFO("after the restart, particles differing in any bit (-1: the ids differ): " << restarted);
    CHECK(restarted == 0);
}

}  // namespace

TEST_CASE("the dam break on N ranks is bitwise the same run in one process on N devices") {
    Scene s = test::small_dam(0.146 / 8);
    s.fluids.front().velocity = {4.0, 0.0, 0.0};  // across the cut between the ranks
    compare(s, 100, [](Options& o) { o.balance = BalanceMode::dynamic; });
}

TEST_CASE("migration across the rank boundary: cuts forced to move every step, no id lost or duplicated") {
    Scene s = test::small_dam(0.146 / 8);
    s.fluids.front().velocity = {2.0, 0.0, 0.0};
    compare(s, 500, [](Options& o) {
        testing::Seams seams;
        seams.cut_schedule = test::sweeping_cuts(static_cast<std::size_t>(ranks_in(*ranks)));
        testing::set_seams(o, seams);
    }, true);
}

TEST_CASE("the halo overlapped with the interior across the rank boundary: bitwise the run in one process") {
    // Arrival order and the fine form: each rank's force pass runs its interior while the
    // particles from the other rank travel (docs/multi_device.md); cuts forced to move every step.
    Scene s = test::small_dam(0.146 / 8);
    s.fluids.front().velocity = {2.0, 0.0, 0.0};
    std::size_t split = 0;
    compare(s, 60, [](Options& o) {
        testing::Seams seams;
        seams.cut_schedule = test::sweeping_cuts(static_cast<std::size_t>(ranks_in(*ranks)));
        testing::set_seams(o, seams);
        o.cell_order = CellOrder::arrival;
        o.interaction = Interaction::fine;
    }, true, &split);
    MESSAGE("force passes split around the halo on this rank: " << split);
    CHECK(split > 0);
}

TEST_CASE("a moving solid across the rank boundary: bitwise the run in one process, checkpoint and restart too") {
    // A paddle in the small tank moved along x and turned about y at once (a CSV motion's
    // linear_rotation interval) while the cuts sweep across it: its particles change ranks.
    Scene s = test::small_tank(0.08, 0.1);
    SolidBox b;
    b.min = {0.14, 0.03, 0.04};
    b.max = {0.17, 0.07, 0.16};
    b.layers = 0;
    MotionSegment m;
    m.type = MotionSegment::Type::linear_rotation;
    m.start = 0.0005;
    m.end = 0.04;
    m.velocity = {1.0, 0.0, 0.1};
    m.axis_point = {0.155, 0.05, 0.1};
    m.axis = {0, 1, 0};
    m.angular_velocity = 4.0;
    b.motion.segments.push_back(m);
    s.solids.push_back(b);
    s.validate();
    compare(s, 200, [](Options& o) {
        testing::Seams seams;
        seams.cut_schedule = test::sweeping_cuts(static_cast<std::size_t>(ranks_in(*ranks)));
        testing::set_seams(o, seams);
    }, true);
}

TEST_CASE("a floating box across the rank boundary: bitwise the run in one process, its state, checkpoint and restart") {
    // A thin tank (a slice periodic in y) with a light box released above its rest draft; its force
    // and moments are summed over both ranks (fixed point). With DBC walls the cuts sweep across the
    // box (its particles on both ranks); with mDBC walls they keep off its ghost nodes' reach.
    for (const std::string method : {"dbc", "mdbc"}) {
        CAPTURE(method);
        const Scene s = Scene::from_json_text(std::string(R"({
  "physics": {"dp": 0.02, "hdp": 1.5, "coefsound": 10, "alpha": 0.1, "alpha_wall": 0.3, "gravity": [0, 0, -9.81]},
  "domain": {"min": [-0.06, 0, -0.06], "max": [0.56, 0.18, 0.4], "periodic": [false, true, false], "split_axis": "x"},
  "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.17, 0.2]}],
  "boundaries": {
    "method": ")") + method + R"(",
    "walls": [{"min": [0, 0, 0], "max": [0.5, 0.16, 0.4], "faces": ["x-", "x+", "z-"], "layers": 2}],
    "boxes": [{"min": [0.20, 0, 0.18], "max": [0.30, 0.16, 0.28], "layers": 0,
               "floating": {"density": 500, "name": "light", "free_translation": [true, false, true],
                            "free_rotation": [false, true, false]}}]
  }
})",
                                              "floating tank");
        // 30 steps: the cuts then split the tank on 2 and on 3 ranks alike (the mDBC cuts keep to
        // two columns, beside the end walls).
        compare(s, 30, [](Options& o) {
            testing::Seams seams;
            seams.cut_schedule = test::sweeping_cuts(static_cast<std::size_t>(ranks_in(*ranks)));
            testing::set_seams(o, seams);
        }, true);
    }
}

TEST_CASE("an inlet and an outlet across the rank boundary: ids unique, bitwise the run in one process, checkpoint too") {
    // Every rank makes the inlet's particles from the same state with the same ids; the slab owning
    // their columns keeps them (docs/scenes.md, inlets). 300 steps: layers made and removed.
    const Scene s = test::open_channel();
    compare(s, 300, [](Options& o) { o.balance = BalanceMode::fixed; }, true);
}

TEST_CASE("an inlet ramping from a series with a profile, and an outlet zone, across the rank boundary: bitwise the run in one process") {
    // Every rank computes the speed, the travelled distance and each profile column's layers alike;
    // the zone's density and removals are per particle (docs/scenes.md, inlets and outlets).
    Scene s = test::open_channel();
    Inlet& in = s.inlets[0];
    in.velocity = {1, 0, 0};
    in.speed.time = {0.0, 0.04, 0.1};
    in.speed.value = {0.5, 0.75, 0.35};
    in.profile.axis = 2;
    in.profile.points = {{0.0, 0.6}, {0.1, 1.2}};
    Outlet zone;
    zone.zone = true;
    zone.min = {0.3, s.domain.min[1], s.domain.min[2]};
    zone.max = {0.36, s.domain.max[1], s.domain.max[2]};
    zone.pressure = 40.0;
    s.outlets.push_back(zone);
    s.validate();
    compare(s, 200, [](Options& o) { o.balance = BalanceMode::fixed; }, true);
}

int main(int argc, char** argv) {
    try {
        ranks = mpi_ranks(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << e.what() << '\n';
        return 1;
    }
    doctest::Context context(argc, argv);
    int failed = 0;
    try {
        failed = context.run();
    } catch (const std::exception& e) {
        abort_all(*ranks, 1, e.what());
    }
    // A failure on one rank only: every rank must exit non-zero.
    int any = failed ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    ranks.reset();
    return any;
}
