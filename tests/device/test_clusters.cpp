// The clusters interaction form (kernels/clusters.cl, neighbour_loop.h -DCLSPH_CLUSTERS): its
// cluster-pair lists against plain C++ on random particles, and the form bitwise the fine form
// (the same terms in the same order) in motion: continuity and summation density, DBC and mDBC,
// a moving solid, Leap-frog and Symplectic, the step ahead and the synchronous path. (Against the
// double-precision reference: test_forces.cpp; on one and three devices: test_interaction_forms.cpp
// and, bitwise, the multi_bitwise case below.)
#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "device/cluster_list.hpp"
#include "device/physics.hpp"
#include "device/sizing.hpp"
#include "support/scenes.hpp"
#include "support/bitwise_state.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

using namespace clsph;
using namespace clsph::device;

namespace {

constexpr std::size_t CS = sizing::kClusterSize;

// Random particles in a 0.16 x 0.14 x 0.12 block at spacing about dp (jittered lattice, a few
// lattice sites left empty so that cells hold different counts).
Particles random_particles(std::mt19937_64& gen, double dp) {
    std::uniform_real_distribution<double> jitter(-0.45 * dp, 0.45 * dp), u(0, 1);
    Particles p;
    std::uint32_t id = 0;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 14; ++j)
            for (int k = 0; k < 12; ++k) {
                if (u(gen) < 0.15) continue;
                const Vec3 x{0.05 + i * dp + jitter(gen), 0.05 + j * dp + jitter(gen), 0.05 + k * dp + jitter(gen)};
                p.push_back(id++, k < 2 ? ParticleType::boundary : ParticleType::fluid, x, {0, 0, 0}, 1000.0f, 0.0f);
            }
    return p;
}

double box_distance(const std::array<double, 6>& a, const std::array<double, 6>& b) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double g = std::max({0.0, b[k] - a[3 + k], a[k] - b[3 + k]});
        d2 += g * g;
    }
    return std::sqrt(d2);
}

using test::differing;
using test::State;
using test::state_of;

// The paddle tank of the motion suite, smaller: a solid box moving through the water.
Scene moving_paddle(bool mdbc) {
    Scene s = test::small_tank(0.1, 0.1);
    SolidBox b;
    b.min = {0.12, 0.03, 0.03};
    b.max = {0.15, 0.07, 0.09};
    b.layers = 0;
    MotionSegment m;
    m.type = MotionSegment::Type::linear;
    m.start = 0;
    m.end = 1;
    m.velocity = {-1.5, 0, 0.3};
    b.motion.segments.push_back(m);
    s.solids.push_back(b);
    s.boundary_method = mdbc ? BoundaryMethod::mdbc : BoundaryMethod::dbc;
    s.validate();
    return s;
}

}  // namespace

TEST_SUITE("physics") {
TEST_CASE("cluster lists: cluster starts and every row's mask as plain C++ finds them, on every device") {
    auto gen = test::rng(3301);
    const double dp = 0.01;
    const Particles in = random_particles(gen, dp);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        for (const int reach : {1, 2}) {
            CAPTURE(reach);
            const double support = 4 * dp;
            Grid grid(Box{{0, 0, 0}, {0.25, 0.22, 0.2}}, support, -1, {false, false, false}, reach);
            ParticleStore ps(*d, grid, in.size());
            ps.upload(in);
            CellPipeline cells(*d, grid);
            cells.run(ps);
            ClusterList list(*d, grid, static_cast<float>(support * support));
            list.build(ps, cells);  // allocates; the second build must write everything again
            d->fill(list.begins(), cl_uint{0xdeadbeefu}, list.capacity());
            const std::size_t rows = grid.rows(), bits = sizing::cluster_mask_bits(reach);
            d->fill(list.masks(), cl_uint{0xdeadbeefu}, list.capacity() * rows * bits / 32);
            list.build(ps, cells);
            const Particles p = ps.download();
            const std::size_t n = p.size(), k = cells.cells();
            std::vector<cl_uint> start(k + 1), cell_of(n), ranges(2 * k * rows), begin(list.capacity());
            std::vector<cl_uint> masks(list.capacity() * rows * bits / 32);
            d->read(cells.cell_start(), start.data(), start.size());
            d->read(ps.vals, cell_of.data(), n);
            d->read(cells.ranges(), ranges.data(), ranges.size());
            d->read(list.begins(), begin.data(), begin.size());
            d->read(list.masks(), masks.data(), masks.size());
            // The clusters, by index (clusters.cl): starts, gaps, the end sentinel; their boxes.
            std::map<std::size_t, std::array<double, 6>> box;
            std::size_t bad_begin = 0;
            for (std::size_t c = 0; c < k; ++c) {
                const std::size_t s = start[c], e = start[c + 1], id0 = c + s / CS, next = c + 1 + e / CS;
                REQUIRE(next >= id0 + (e - s + CS - 1) / CS);
                REQUIRE(next <= id0 + (e - s + CS - 1) / CS + 1);
                for (std::size_t id = id0, b = s; id < next; ++id, b += CS) {
                    const std::size_t want = std::min(b, e);
                    bad_begin += begin[id] != want;
                    if (b >= e) continue;
                    std::array<double, 6> bx{1e9, 1e9, 1e9, -1e9, -1e9, -1e9};
                    for (std::size_t j = b; j < std::min(b + CS, e); ++j)
                        for (int a = 0; a < 3; ++a) {
                            bx[a] = std::min(bx[a], p.position[j][a]);
                            bx[3 + a] = std::max(bx[3 + a], p.position[j][a]);
                        }
                    box[id] = bx;
                }
                if (c + 1 == k) bad_begin += begin[next] != n;
            }
            CHECK(bad_begin == 0);
            // Each i-cluster's rows: a bit for every cluster whose box comes within the support
            // (1e-4 of it spare for the device's float boxes), none for one beyond 1.001 supports.
            std::size_t missing = 0, needless = 0, whole_rows = 0, checked_rows = 0;
            double fine_candidates = 0, cluster_candidates = 0;
            for (std::size_t c = 0; c < k; ++c)
                for (std::size_t s = start[c]; s < start[c + 1]; s += CS) {
                    const std::size_t id = c + start[c] / CS + (s - start[c]) / CS;
                    const std::size_t members = std::min(s + CS, std::size_t{start[c + 1]}) - s;
                    for (std::size_t r = 0; r < rows; ++r) {
                        const std::size_t x = ranges[2 * (c * rows + r)], y = ranges[2 * (c * rows + r) + 1];
                        const std::size_t at = (id * rows + r) * bits / 32;
                        const std::uint64_t m = bits == 64 ? masks[at] | std::uint64_t{masks[at + 1]} << 32 : masks[at];
                        if (x >= y) {
                            CHECK(m == 0);
                            continue;
                        }
                        fine_candidates += double(members * (y - x));
                        const std::size_t jc0 = cell_of[x] + x / CS, count = cell_of[y - 1] + 1 + y / CS - jc0;
                        if (count > bits) {
                            ++whole_rows;
                            cluster_candidates += double(members * (y - x));
                            continue;
                        }
                        ++checked_rows;
                        for (std::size_t t = 0; t < count; ++t) {
                            const bool set = (m >> t) & 1u;
                            const auto jb = box.find(jc0 + t);
                            if (jb == box.end()) {  // a gap: never listed
                                needless += set;
                                continue;
                            }
                            const double dist = box_distance(box.at(id), jb->second);
                            if (set) cluster_candidates += double(members * (begin[jc0 + t + 1] - begin[jc0 + t]));
                            if (dist < support * (1 - 1e-4) && !set) ++missing;
                            if (dist > support * 1.001 && set) ++needless;
                        }
                    }
                }
            MESSAGE(d->label() << ", reach " << reach << ": " << n << " particles, " << checked_rows << " rows by mask, "
                               << whole_rows << " whole; candidates " << cluster_candidates << " against the fine form's "
                               << fine_candidates);
            CHECK(checked_rows > 0);
            CHECK(missing == 0);
            CHECK(needless == 0);
            CHECK(cluster_candidates < fine_candidates);  // the boxes prune (by how much: the MESSAGE)
        }
    }
}

TEST_CASE("run.list_buffer with what else moves, makes or removes particles is refused, naming the key and why") {
    Scene symplectic = test::small_tank(0.1, 0.1);
    symplectic.physics.integrator = Integrator::symplectic;
    const std::pair<Scene, const char*> cases[] = {{symplectic, "Symplectic"}, {moving_paddle(false), "moving solids"}};
    for (auto [scene, why] : cases) {
        CAPTURE(why);
        scene.run.list_buffer = 0.1;
        Options o;
        o.devices = test::validation_device_spec();
        try {
            Simulation sim(scene, o);
            FAIL("accepted");
        } catch (const SceneError& e) {
            const std::string what = e.what();
            CAPTURE(what);
            CHECK(what.find("run.list_buffer") != std::string::npos);
            CHECK(what.find(why) != std::string::npos);
        }
    }
}

TEST_CASE("the clusters form is bitwise the fine form in motion") {
    // One device (pocl's threaded one where present: each Simulation builds its programs, which on
    // rusticl takes seconds); every device runs one force pass of each configuration bitwise
    // against the fine form in test_forces.cpp.
    struct Config {
        const char* what;
        Scene scene;
        bool synchronous;
    };
    Scene summation = moving_paddle(true);
    summation.physics.density = DensityMode::summation;
    Scene symplectic = moving_paddle(false);
    symplectic.physics.integrator = Integrator::symplectic;
    Scene no_slip = moving_paddle(true);  // the walls' mirrored velocities (kernels/wall_velocity.h)
    no_slip.wall_slip = WallSlip::no_slip;
    no_slip.physics.viscosity = Viscosity::laminar_sps;
    no_slip.physics.kinematic_viscosity = 1e-3;
    const Config configs[] = {{"moving solid, continuity, DBC, the step ahead", moving_paddle(false), false},
                              {"moving solid, summation density, mDBC, synchronous", summation, true},
                              {"moving solid, Symplectic", symplectic, false},
                              {"moving solid, mDBC no-slip walls, laminar+sps, the step ahead", no_slip, false}};
    const int steps = 12;
    for (const auto& c : configs) {
        CAPTURE(c.what);
        State got[2];
        for (int f = 0; f < 2; ++f) {
            Options o;
            o.devices = test::validation_device_spec();
            o.interaction = f == 0 ? Interaction::fine : Interaction::clusters;
            o.synchronous = c.synchronous;
            Simulation sim(c.scene, o);
            CHECK(sim.shares().at(0).interaction == o.interaction);
            for (int k = 0; k < steps; ++k) sim.step();
            got[f] = state_of(sim);
        }
        REQUIRE(!got[0].empty());
        CHECK(differing(got[0], got[1]) == 0);
    }
}
}

TEST_SUITE("multi_bitwise") {
TEST_CASE("the clusters form: bitwise the same on 1, 2 and 3 devices, and bitwise the fine form") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    Scene scene = test::small_dam(0.0073);
    scene.fluids.front().velocity = {4.0, 0.0, 0.0};  // across the cuts: cells mix arrivals and stayers
    const int steps = 25;
    Options fine;
    fine.devices = test::device_spec(1);
    fine.interaction = Interaction::fine;
    Simulation ref(scene, fine);
    for (int k = 0; k < steps; ++k) ref.step();
    const State want = state_of(ref);
    for (std::size_t count = 1; count <= std::min<std::size_t>(3, devs.size()); ++count) {
        CAPTURE(count);
        Options o;
        o.devices = test::device_spec(count);
        o.interaction = Interaction::clusters;
        Simulation sim(scene, o);
        for (int k = 0; k < steps; ++k) sim.step();
        CHECK(sim.time() == ref.time());
        CHECK(differing(state_of(sim), want) == 0);
    }
}
}

TEST_SUITE("multi_bitwise") {
TEST_CASE("tables kept over steps (run.list_buffer): bitwise the same on 1, 2 and 3 devices, fine and clusters alike, and near the run sorted every step") {
    const auto devs = test::devices();
    REQUIRE(devs.size() >= 2);
    const int steps = 40;
    for (const bool mdbc : {false, true}) {
        CAPTURE(mdbc);
        Scene scene = test::small_dam(0.0073);
        // Across the cuts, and builds due every few steps (mDBC's walls take 4 m/s badly: 2).
        scene.fluids.front().velocity = {mdbc ? 2.0 : 4.0, 0.0, 0.0};
        // The period 10 dp instead of 8: three cells of a support and the buffer.
        const double dp = scene.physics.dp;
        scene.domain.max[1] = 10 * dp;
        scene.walls.front().max[1] = 9 * dp;
        scene.fluids.front().max[1] = 9.5 * dp;
        if (mdbc) scene.boundary_method = BoundaryMethod::mdbc;
        Scene kept = scene;
        kept.run.list_buffer = 0.15;
        // ahead: the step ahead (docs/multi_device.md, "The step ahead on several devices"), up to
        // eight steps in flight, the builds synchronous.
        auto run = [&](const Scene& s, std::size_t count, Interaction form, TableBuilds* builds, bool ahead = false) {
            Options o;
            o.devices = test::device_spec(count);
            o.interaction = form;
            o.synchronous = !ahead;
            o.step_limit = steps;
            Simulation sim(s, o);
            CHECK(sim.steps_ahead() == ahead);
            if (ahead)
                sim.run_until(1e9);  // to the step limit
            else
                for (int k = 0; k < steps; ++k) sim.step();
            CHECK(sim.info().step == std::uint64_t(steps));
            if (builds) *builds = sim.table_builds();
            return sim.particles();
        };
        TableBuilds want_builds;
        const Particles ref = run(kept, 1, Interaction::fine, &want_builds);
        const State want = state_of(ref);
        MESSAGE(std::string(mdbc ? "mDBC: " : "DBC: ") << want_builds.builds << " builds in " << steps << " steps");
        CHECK(want_builds.builds > 1);                 // rebuilt when due
        CHECK(want_builds.builds < steps / 2);         // and kept in between
        CHECK(want_builds.age < std::size_t(steps));
        const std::tuple<std::size_t, Interaction, bool> runs[] = {
            {2, Interaction::fine, false}, {3, Interaction::fine, false}, {1, Interaction::clusters, false},
            {3, Interaction::clusters, false}, {1, Interaction::fine, true}, {2, Interaction::fine, true},
            {3, Interaction::clusters, true}};
        for (const auto& [count, form, ahead] : runs) {
            if (count > devs.size()) continue;
            CAPTURE(count);
            CAPTURE(std::string(interaction_name(form)));
            CAPTURE(ahead);
            TableBuilds b;
            CHECK(differing(state_of(run(kept, count, form, &b, ahead)), want) == 0);
            CHECK(b.builds == want_builds.builds);
        }
        // The run sorted every step sums the same terms in another order: round-off apart.
        Scene sorted = scene;
        const Particles every = run(sorted, 1, Interaction::fine, nullptr);
        REQUIRE(every.size() == ref.size());
        std::map<std::uint32_t, std::size_t> at;
        for (std::size_t i = 0; i < every.size(); ++i) at[every.id[i]] = i;
        double worst = 0;
        for (std::size_t i = 0; i < ref.size(); ++i) {
            const auto& a = ref.position[i];
            const auto& b = every.position[at.at(ref.id[i])];
            worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
        }
        MESSAGE("largest distance to the run sorted every step: " << worst << " m");
        CHECK(worst < 1e-3 * scene.physics.dp);
    }
}
}
