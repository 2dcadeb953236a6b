// Every interaction form, forced, on one device and on several, against the fine form on one
// device: the same particles after a few steps of a small dam break, within round-off. The scene
// has a support of 4 dp, so the grid runs at reach 2 (cells of half a support along a and b).
#include "clsph/simulation.hpp"
#include "device/physics.hpp"
#include "support/scenes.hpp"
#include "support/skip.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

using namespace clsph;

namespace {

Particles run(const Scene& scene, Interaction form, std::size_t devices, int steps) {
    Options o;
    o.devices = test::device_spec(devices);
    o.interaction = form;
    Simulation sim(scene, o);
    for (const auto& sh : sim.shares()) {
        CHECK(sh.interaction == form);
        // The order within cells left to auto: morton where every device runs lanes.
        CHECK(sh.cell_order == (form == Interaction::lanes ? CellOrder::morton : CellOrder::arrival));
    }
    for (int i = 0; i < steps; ++i) sim.step();
    return sim.particles();
}

// Every form but clusters (bitwise the fine form's on any device count: test_clusters.cpp) on one
// device and on `several` (1: one device only), against the fine form on one device.
void forms_follow_fine(const Scene& scene, std::size_t several) {
    const int steps = 20;
    const Particles ref = run(scene, Interaction::fine, 1, steps);
    std::map<std::uint32_t, std::size_t> ref_at;
    for (std::size_t i = 0; i < ref.size(); ++i) ref_at[ref.id[i]] = i;
    REQUIRE(ref_at.size() == ref.size());
    const std::vector<std::size_t> counts = several > 1 ? std::vector<std::size_t>{1, several} : std::vector<std::size_t>{1};
    for (const Interaction form : interaction_forms())
        for (const std::size_t count : counts) {
            if (count < 2 && form == Interaction::fine) continue;  // the reference itself
            // Bitwise the fine form's on any device count (test_clusters.cpp): nothing to add here.
            if (form == Interaction::clusters) continue;
            CAPTURE(std::string(interaction_name(form)));
            CAPTURE(count);
            const Particles p = run(scene, form, count, steps);
            REQUIRE(p.size() == ref.size());
            double worst = 0, worst_v = 0;
            for (std::size_t i = 0; i < p.size(); ++i) {
                const auto it = ref_at.find(p.id[i]);
                REQUIRE(it != ref_at.end());
                for (int k = 0; k < 3; ++k) {
                    worst = std::max(worst, std::abs(p.position[i][k] - ref.position[it->second][k]));
                    worst_v = std::max(worst_v, double(std::abs(p.velocity[i][k] - ref.velocity[it->second][k])));
                }
            }
            MESSAGE(std::string(interaction_name(form)) << " on " << count << " device(s): largest position difference " << worst
                                           << " m, velocity " << worst_v << " m/s after " << steps << " steps");
            CHECK(worst < 1e-6);  // m: round-off, not a different physics (2e-9 m seen on pocl and rusticl)
            CHECK(worst_v < 1e-4);
        }
}

}  // namespace

TEST_SUITE("physics") {
TEST_CASE("every interaction form, on one device and on three, follows the fine form on one device") {
    const std::size_t several = std::min<std::size_t>(3, test::devices().size());
    if (several < 2) test_skip::skip("interaction forms on three devices: one device only (POCL_DEVICES=\"basic pthread\")");
    forms_follow_fine(test::small_tank(0.1, 0.2), several);
    // mDBC no-slip walls: every form reads the walls' mirrored velocities (kernels/wall_velocity.h).
    Scene no_slip = test::small_tank(0.1, 0.2);
    no_slip.boundary_method = BoundaryMethod::mdbc;
    no_slip.wall_slip = WallSlip::no_slip;
    no_slip.physics.viscosity = Viscosity::laminar;
    no_slip.physics.kinematic_viscosity = 1e-3;
    forms_follow_fine(no_slip, 1);  // on one device: several devices with no-slip walls are multi_bitwise's
}
}

TEST_SUITE("physics") {
TEST_CASE("the automatic interaction form: lanes on pocl CPUs, fine on GPUs and rusticl") {
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        const bool pocl_cpu = d->info().is_cpu() && d->info().platform.find("Portable Computing Language") != std::string::npos;
        const Interaction expected = pocl_cpu ? Interaction::lanes : Interaction::fine;
        CHECK(device::interaction_for(Interaction::automatic, *d) == expected);
        for (const Interaction form : interaction_forms()) CHECK(device::interaction_for(form, *d) == form);
    }
}
}
