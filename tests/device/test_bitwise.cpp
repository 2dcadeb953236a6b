// Results that do not depend on the device count: the same scene on 1, 2 and 3 devices of one
// OpenCL implementation leaves a bitwise-identical state after 100 steps. It holds because every
// device's sort input is a subsequence of what one device would sort (arrivals from the left |
// kept particles in their previous order | arrivals from the right) and the radix sort is stable,
// so every cell lists its particles in the order one device would, and every neighbour sum adds
// the same terms in the same order. CTest runs this suite with POCL_DEVICES="pthread pthread pthread".
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"
#include "support/cut_schedules.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <functional>
#include <memory>
#include <map>

using namespace clsph;

namespace {

// The same, the water moving along the split axis at 4 m/s: in 100 steps it crosses cuts and halo
// columns, so cells hold particles that arrived from another device next to ones that stayed
// (without that, every cell's particles come from one device and any order would pass).
Scene sliding_dam(double dp) {
    Scene s = test::small_dam(dp);
    s.fluids.front().velocity = {4.0, 0.0, 0.0};
    return s;
}

// Particles by id, as raw bytes: position (double from the cell key and float offset), velocity,
// density.
struct State {
    std::map<std::uint32_t, std::array<double, 3>> pos;
    std::map<std::uint32_t, std::array<float, 4>> velrho;
};
State state_of(Simulation& sim) {
    const Particles p = sim.particles();
    State s;
    for (std::size_t i = 0; i < p.size(); ++i) {
        s.pos[p.id[i]] = p.position[i];
        s.velrho[p.id[i]] = {p.velocity[i][0], p.velocity[i][1], p.velocity[i][2], p.density[i]};
    }
    return s;
}

// How many particles differ in any bit (positions, velocities or densities), or -1 when the ids differ.
long differing(const State& a, const State& b) {
    if (a.pos.size() != b.pos.size()) return -1;
    long n = 0;
    for (const auto& [id, x] : a.pos) {
        auto it = b.pos.find(id);
        if (it == b.pos.end()) return -1;
        n += std::memcmp(x.data(), it->second.data(), sizeof x) != 0 ||
             std::memcmp(a.velrho.at(id).data(), b.velrho.at(id).data(), sizeof(float) * 4) != 0;
    }
    return n;
}

// Steps `sims` in lockstep for `steps` steps, comparing every device count with the first
// (one device) now and then; returns the first step at which any differs (-1: none).
int first_difference(std::vector<std::unique_ptr<Simulation>>& sims, int steps) {
    for (int i = 0; i <= steps; ++i) {
        if (i > 0)
            for (auto& s : sims) s->step();
        if (!(i <= 10 || i % 10 == 0 || i == steps)) continue;
        const State ref = state_of(*sims[0]);
        for (std::size_t k = 1; k < sims.size(); ++k) {
            if (sims[k]->time() != sims[0]->time()) return i;  // dt comes from max reductions: exact
            const State st = state_of(*sims[k]);
            const long d = differing(st, ref);
            if (d == 0) continue;
            MESSAGE((k + 1) << " devices, step " << i << ": " << d << " particles differ");
            return i;
        }
    }
    return -1;
}

std::vector<std::unique_ptr<Simulation>> on_1_2_3(const Scene& scene, const std::function<Options(std::size_t)>& options) {
    const auto devs = test::devices();
    if (devs.size() < 2) MESSAGE("needs at least two devices of one implementation, found " << devs.size());
    REQUIRE(devs.size() >= 2);
    std::vector<std::unique_ptr<Simulation>> sims;
    for (std::size_t count = 1; count <= std::min<std::size_t>(3, devs.size()); ++count) {
        Options o = options(count);
        o.devices = test::device_spec(count);
        sims.push_back(std::make_unique<Simulation>(scene, o));
    }
    return sims;
}

// Options whose cuts sweep across the domain on D > 1 devices (one device: the defaults).
Options sweeping_cuts_options(std::size_t D) {
    Options o;
    if (D == 1) return o;
    testing::Seams seams;
    seams.cut_schedule = test::sweeping_cuts(D);
    testing::set_seams(o, seams);
    return o;
}

}  // namespace

TEST_SUITE("multi_bitwise") {
TEST_CASE("the same scene on 1, 2 and 3 devices is bitwise identical after 100 steps") {
    auto still = on_1_2_3(test::small_dam(0.146 / 8), [](std::size_t) { return Options{}; });
    CHECK(first_difference(still, 100) == -1);
    auto sims = on_1_2_3(sliding_dam(0.146 / 8), [](std::size_t) { return Options{}; });
    CHECK(first_difference(sims, 100) == -1);
}

TEST_CASE("bitwise identical while cuts sweep: narrow slabs, idle devices, particles crossing every step") {
    // The cuts move one or two columns a step, leaving a device with a single column or none.
    auto sims = on_1_2_3(sliding_dam(0.146 / 8), sweeping_cuts_options);
    CHECK(first_difference(sims, 100) == -1);
}

TEST_CASE("mDBC: bitwise identical on 1, 2 and 3 devices while cuts sweep across the walls") {
    // Boundary densities come from ghost nodes up to 5 dp inside the fluid; each owner computes its
    // own and its neighbours get them with the next exchange. The sweep asks for cuts everywhere,
    // the end walls' (normal to the split axis) included: where an owner would lack the fluid
    // around a ghost node the cut moves to the nearest column where it may go.
    // (At 4 m/s, Mach 0.24, the impulsive start compresses the water by 23 %: the ghost nodes'
    // gradient extrapolated 5 dp into the walls takes their density past the 1.3 rho0 band.)
    Scene scene = test::small_dam(0.146 / 8);
    scene.fluids.front().velocity = {1.0, 0.0, 0.0};
    scene.boundary_method = BoundaryMethod::mdbc;
    auto sims = on_1_2_3(scene, sweeping_cuts_options);
    CHECK(first_difference(sims, 100) == -1);
    // And with the balancer choosing the cuts.
    auto balanced = on_1_2_3(scene, [](std::size_t) { return Options{}; });
    CHECK(first_difference(balanced, 100) == -1);
}

TEST_CASE("mDBC no-slip walls: bitwise identical on 1, 2 and 3 devices while cuts sweep (laminar+sps)") {
    // Each owner writes its boundary particles' v_wall - v_G into their accelerations' xyz
    // (kernels/wall_velocity.h), which every exchange carries with the particle: the ghosts'
    // mirrored velocities are their owners' bits, on one halo column (laminar) or two (SPS). SPS
    // only: its laminar term reads the mirror as laminar does, and CI's time is short.
    Scene scene = test::small_dam(0.146 / 8);
    scene.fluids.front().velocity = {1.0, 0.0, 0.0};
    scene.boundary_method = BoundaryMethod::mdbc;
    scene.wall_slip = WallSlip::no_slip;
    scene.physics.kinematic_viscosity = 1e-3;
    scene.physics.viscosity = Viscosity::laminar_sps;
    auto sims = on_1_2_3(scene, sweeping_cuts_options);
    CHECK(first_difference(sims, 100) == -1);
    Scene wall = scene;  // and the mirror was there: the walls' own velocity gives another flow
    wall.wall_slip = WallSlip::wall;
    Options o;
    o.devices = test::device_spec(1);
    Simulation plain(wall, o);
    for (int k = 0; k < 100; ++k) plain.step();
    CHECK(differing(state_of(plain), state_of(*sims[0])) > 0);
}

TEST_CASE("laminar viscosity: bitwise identical on 1, 2 and 3 devices while cuts sweep") {
    // The laminar term adds no state: each pair's term from both particles' velocities and
    // densities, summed in the fine form's order. nu large enough to matter in 100 steps.
    Scene scene = sliding_dam(0.146 / 8);
    scene.physics.viscosity = Viscosity::laminar;
    scene.physics.kinematic_viscosity = 1e-3;
    auto sims = on_1_2_3(scene, sweeping_cuts_options);
    CHECK(first_difference(sims, 100) == -1);
}

TEST_CASE("laminar+sps: bitwise identical on 1, 2 and 3 devices while cuts sweep (two halo columns)") {
    // Each device computes the stress of its ghosts one column out from their neighbours, which
    // the second halo column brings: the owner's bits. Sweeping cuts leave slabs one column wide.
    Scene scene = sliding_dam(0.146 / 8);
    scene.physics.viscosity = Viscosity::laminar_sps;
    scene.physics.kinematic_viscosity = 1e-6;
    for (const bool sweep : {true, false}) {
        CAPTURE(sweep);
        auto sims = on_1_2_3(scene, [&](std::size_t D) { return sweep ? sweeping_cuts_options(D) : Options{}; });
        CHECK(first_difference(sims, 100) == -1);
    }
}

TEST_CASE("summation density: bitwise identical on 1, 2 and 3 devices while cuts sweep (two halo columns)") {
    // The force pass reads its neighbours' densities of this step's summation pass: each device
    // sums its ghosts one column out too, from the second halo column. Before, the ghosts kept
    // their owners' densities of the step before: on two devices 1,096 particles differed from
    // one device's after the first step. The clusters form builds its lists over the ghosts too.
    Scene scene = sliding_dam(0.146 / 8);
    scene.physics.density = DensityMode::summation;
    for (const Interaction form : {Interaction::fine, Interaction::clusters}) {
        CAPTURE(std::string(interaction_name(form)));
        auto sims = on_1_2_3(scene, [&](std::size_t D) {
            Options o = sweeping_cuts_options(D);
            o.interaction = form;
            return o;
        });
        CHECK(first_difference(sims, 60) == -1);
    }
}

TEST_CASE("both orders within cells: bitwise identical on 1, 2 and 3 devices while cuts sweep") {
    // Morton order (CellOrder::morton) sorts each cell's particles once more after every merge; a
    // cell must come out in the same order whichever device holds it and however its particles
    // arrived (kept, from the left, from the right, as ghosts). On pocl `auto` is morton already
    // (every device runs lanes): arrival is the order asked for here.
    for (const CellOrder order : {CellOrder::arrival, CellOrder::morton}) {
        CAPTURE(std::string(cell_order_name(order)));
        auto sims = on_1_2_3(sliding_dam(0.146 / 8), [&](std::size_t D) {
            Options o = sweeping_cuts_options(D);
            o.cell_order = order;
            return o;
        });
        for (const auto& sim : sims) CHECK(sim->cell_order() == order);
        CHECK(sims.front()->shares().front().cell_order == order);
        CHECK(first_difference(sims, 60) == -1);
    }
}

TEST_CASE("the halo overlapped with the interior's forces: bitwise the whole pass on 1, 2 and 3 devices") {
    // With several devices the forces of the owned particles two columns or more inside a device's
    // old columns run while the arrivals travel, on tables of the kept particles alone; the rest
    // after the merge. The merge's sorts must leave those forces alone (the edge sort once
    // borrowed the scratch they sit in: 258 particles differed on three devices by step 20), and
    // their tables must list each cell as the merged ones do. Cuts sweep, so slabs grow, shrink
    // and move by two columns a step; each form, mDBC with no-slip walls (the pass after the
    // forces, and forces that read the walls' velocities) and Symplectic (two split passes a step). Arrival order: the morton order moves
    // particles within cells after the merge, and runs the whole pass.
    Scene mdbc = test::small_dam(0.146 / 8);
    mdbc.fluids.front().velocity = {1.0, 0.0, 0.0};
    mdbc.boundary_method = BoundaryMethod::mdbc;
    mdbc.wall_slip = WallSlip::no_slip;
    Scene symplectic = sliding_dam(0.146 / 8);
    symplectic.physics.integrator = Integrator::symplectic;  // two exchanges and split passes a step
    struct Case { const char* name; Scene scene; Interaction form; };
    const Case cases[] = {{"sliding dam, fine", sliding_dam(0.146 / 8), Interaction::fine},
                          {"sliding dam, lanes", sliding_dam(0.146 / 8), Interaction::lanes},
                          {"mDBC, no-slip, fine", mdbc, Interaction::fine},
                          {"Symplectic, fine", symplectic, Interaction::fine}};
    for (const Case& c : cases) {
        CAPTURE(std::string(c.name));
        auto options = [&](std::size_t D, bool whole) {
            Options o;
            testing::Seams seams;
            if (D > 1) seams.cut_schedule = test::sweeping_cuts(D);
            seams.whole_force_pass = whole;
            testing::set_seams(o, seams);
            o.cell_order = CellOrder::arrival;
            o.interaction = c.form;
            return o;
        };
        auto sims = on_1_2_3(c.scene, [&](std::size_t D) { return options(D, false); });
        const std::size_t overlapped = sims.size();
        if (test::devices().size() >= 3) {  // and three devices with the whole pass after the merge
            Options o = options(3, true);
            o.devices = test::device_spec(3);
            sims.push_back(std::make_unique<Simulation>(c.scene, o));
        }
        CHECK(first_difference(sims, 40) == -1);
        for (std::size_t k = 0; k < sims.size(); ++k) {
            std::size_t passes = 0;
            for (const auto& share : sims[k]->shares()) passes += share.split_force_passes;
            const std::string how = k >= overlapped ? " (whole pass)" : "";
            MESSAGE(std::string(c.name) << ", " << sims[k]->shares().size() << " devices" << how << ": " << passes
                                        << " force passes split around the halo");
            if (k == 0 || k >= overlapped)
                CHECK(passes == 0);  // one device has no halo; the seam turns the split off
            else
                CHECK(passes > 0);
        }
    }
}

TEST_CASE("Symplectic: bitwise identical on 1, 2 and 3 devices (two exchanges and force passes a step)") {
    Scene scene = sliding_dam(0.146 / 8);
    scene.physics.integrator = Integrator::symplectic;
    auto sims = on_1_2_3(scene, [](std::size_t) { return Options{}; });
    CHECK(first_difference(sims, 60) == -1);
}

TEST_CASE("bitwise identical with a narrow slab inside the fluid, particles arriving from both sides") {
    // A slab of two or three columns sorts everything it holds once the arrivals are in (its edges
    // would overlap): the order there must be canonical too.
    auto sims = on_1_2_3(sliding_dam(0.146 / 8), [](std::size_t D) {
        Options o;
        if (D == 1) return o;
        testing::Seams seams;
        seams.cut_schedule = [D](std::uint64_t step, std::size_t columns) {
            const std::size_t w = step % 2;
            if (D == 2) return std::vector<std::size_t>{0, 2 + w, columns};
            return std::vector<std::size_t>{0, 1 + w, 3 + w + step % 3 / 2, columns};
        };
        testing::set_seams(o, seams);
        return o;
    });
    CHECK(first_difference(sims, 100) == -1);
}

TEST_CASE("one device opened as 2 and 4 slabs is bitwise the one-slab run, the balancer moving the cuts") {
    // What the bench's --slabs measures (Seams::slabs: the device opened several times on one
    // context), with the exchange as it is now: each edge sorted alone on the bits of its few
    // columns, a side without arrivals not sorted at all, and the drift enqueued with the settle
    // after the balancer has moved the cuts (which then move by whole columns, past the bounds
    // the edges' sorts start from).
    // Three slabs cut at a quarter and three quarters besides: the middle one wide enough for its edges, with arrivals on
    // both sides, so both edges sort with their bounds.
    // On pocl's pthread device. Several slabs of one pocl device used to stop now and then in pocl
    // 3.1's own assertion (pocl_release_dlhandle_cache), since they shared each kernel's compiled
    // library; each slab now builds its own (Quirks::build_salt; test_runtime.cpp).
    // In pocl's default order (morton) and in arrival order, where the slabs' force passes are
    // split around the halo (the interior while the arrivals travel: docs/multi_device.md).
    for (const CellOrder order : {CellOrder::automatic, CellOrder::arrival}) {
        CAPTURE(std::string(cell_order_name(order)));
        std::vector<std::unique_ptr<Simulation>> sims;
        for (const std::size_t slabs : {1u, 2u, 4u, 3u}) {
            Options o;
            o.devices = test::validation_device_spec();
            o.capacity_headroom = 5.0;  // room in the reorder scratch for the edges of a scene this small
            o.cell_order = order;
            if (slabs > 1) {
                testing::Seams seams;
                seams.slabs = slabs;
                if (slabs == 3)
                    seams.cut_schedule = [](std::uint64_t, std::size_t columns) {
                        return std::vector<std::size_t>{0, columns / 4, 3 * columns / 4, columns};
                    };
                testing::set_seams(o, seams);
            }
            sims.push_back(std::make_unique<Simulation>(sliding_dam(0.146 / 8), o));
            CHECK(sims.back()->memory().size() == slabs);
        }
        CHECK(first_difference(sims, 100) == -1);
        if (order != CellOrder::arrival) continue;
        for (std::size_t k = 1; k < sims.size(); ++k) {
            std::size_t split = 0;
            for (const auto& share : sims[k]->shares()) split += share.split_force_passes;
            MESSAGE(sims[k]->shares().size() << " slabs in arrival order: " << split << " force passes split around the halo");
            CHECK(split > 0);
        }
    }
}

TEST_CASE("bitwise identical when every exchange sends from whole slabs and sorts once") {
    // The path a particle that jumped more than a column takes: every device sorts all it holds
    // with every arrival, so every cell where particles from two devices meet is ordered by it.
    auto sims = on_1_2_3(sliding_dam(0.146 / 8), [](std::size_t) {
        Options o;
        testing::Seams seams;
        seams.wide_exchange = true;
        testing::set_seams(o, seams);
        return o;
    });
    CHECK(first_difference(sims, 100) == -1);
}
}
