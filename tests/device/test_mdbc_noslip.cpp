// mDBC no-slip walls (boundaries.slip "no-slip"; kernels/mdbc.cl, mdbc_lanes.cl, wall_velocity.h):
// the mDBC pass's fluid velocity at each boundary particle's ghost node, as v_wall - v_G in the
// xyz of the force pass's output, against plain C++ double on random inputs, on every device, in
// the fine form and the CPU (lanes) form: random ghost offsets (some outside the domain, some in
// cells far from the particle's), random wall velocities, fluid of random velocities, or of a
// linear velocity field, which the first-order correction reproduces at the node exactly. The
// output is poisoned (NaN) so that unwritten entries show, and its w (the force pass's drho/dt of
// the particle) must come through.
#include "device/cell_pipeline.hpp"
#include "device/physics.hpp"
#include "support/mdbc_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace clsph;
using namespace clsph::device;

namespace {

Scene floor_scene(double dp) {
    Scene s;
    s.physics.dp = dp;
    s.physics.c0 = 20.0;
    s.boundary_method = BoundaryMethod::mdbc;
    s.wall_slip = WallSlip::no_slip;
    s.domain.min = {-0.1, -0.1, -0.1};
    s.domain.max = {0.4, 0.3, 0.3};
    return s;
}

// The linear field of the second round: v = a + B x.
std::array<double, 3> linear_field(const Vec3& x) {
    return {0.3 + 2.0 * x[0] - 1.0 * x[2], -0.2 + 0.5 * x[1], 0.1 + 1.5 * x[0] + 3.0 * x[2]};
}

}  // namespace

TEST_SUITE("mdbc") {
TEST_CASE("mdbc no-slip: the fluid's velocity at each ghost node matches plain C++ on every device, fine and lanes") {
    const Scene s = floor_scene(0.02);
    Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support(), 0, {false, false, false},
              reach_for(s.physics.support(), s.physics.dp));
    const double dp = s.physics.dp;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float w_mark = 0.25f;  // the output's w before the pass (drho/dt): kept
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(2291);
        for (const Interaction form : {Interaction::fine, Interaction::lanes}) {
            CAPTURE(std::string(interaction_name(form)));
            Physics phys(*d, grid, s, form);
            REQUIRE(phys.no_slip());
            REQUIRE(phys.interaction() == form);
            const SphParams sp = phys.params();
            CellPipeline cells(*d, grid);
            for (const bool linear : {false, true})
                for (std::size_t fluid_n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{37}, std::size_t{3000}}) {
                    CAPTURE(linear);
                    CAPTURE(fluid_n);
                    std::uniform_real_distribution<double> ux(0.0, 0.3), uy(0.0, 0.2), uz(0.5 * dp, 8 * dp),
                        rho(990.0, 1010.0), mir(-5 * dp, 5 * dp), vel(-1.0, 1.0);
                    Particles p;
                    std::vector<std::array<float, 3>> by_id;
                    // A floor of three layers (ids first), some with random ghost offsets and some
                    // moving (a wall velocity of their own), then fluid above it.
                    for (int i = 0; i <= 15; ++i)
                        for (int j = 0; j <= 10; ++j)
                            for (int l = 0; l < 3; ++l) {
                                std::array<float, 3> m{0.0f, 0.0f, static_cast<float>((2 * l + 1) * dp)};
                                if (gen() % 4 == 0) m = {float(mir(gen)), float(mir(gen)), float(std::abs(mir(gen)))};
                                by_id.push_back(m);
                                std::array<float, 3> v{0.0f, 0.0f, 0.0f};
                                if (gen() % 3 == 0) v = {float(vel(gen)), float(vel(gen)), float(vel(gen))};
                                p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::boundary,
                                            {i * dp, j * dp, -l * dp}, v, nan, 0.0f);
                            }
                    for (std::size_t k = 0; k < fluid_n; ++k) {
                        const Vec3 x{ux(gen), uy(gen), uz(gen)};
                        std::array<float, 3> v{float(vel(gen)), float(vel(gen)), float(vel(gen))};
                        if (linear) {
                            const auto f = linear_field(x);
                            v = {float(f[0]), float(f[1]), float(f[2])};
                        }
                        p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, x, v,
                                    static_cast<float>(rho(gen)), 0.0f);
                    }
                    // The velocities the reference reads are the floats the device holds.
                    phys.set_ghost_nodes(by_id);
                    ParticleStore ps(*d, grid, p.size());
                    ps.upload(p);
                    cells.run(ps);
                    const std::size_t n = ps.ranges.owned;
                    cl_rt::Buffer out = d->alloc(4 * sizeof(float) * n, "no-slip output");
                    std::vector<float> poison(4 * n, nan);
                    for (std::size_t i = 0; i < n; ++i) poison[4 * i + 3] = w_mark;
                    d->write(out, poison.data(), poison.size());
                    phys.boundary_densities(ps, cells, out);
                    const Particles got = ps.download();
                    std::vector<float> seen(4 * n);
                    d->read(out, seen.data(), seen.size());
                    REQUIRE(got.size() == p.size());
                    std::size_t wrong = 0, corrected = 0, shepard = 0, none = 0, skipped = 0, moving = 0;
                    std::size_t linear_checked = 0;
                    double worst = 0;
                    for (std::size_t i = 0; i < got.size(); ++i) {
                        const float* o = &seen[4 * i];
                        CHECK(std::memcmp(&o[3], &w_mark, sizeof w_mark) == 0);  // w kept
                        if (got.type[i] == ParticleType::fluid) {  // not written: still the poison
                            CHECK(std::isnan(o[0]));
                            CHECK(got.velocity[i] == p.velocity[got.id[i]]);  // velocities are only read
                            continue;
                        }
                        REQUIRE(std::isfinite(o[0]));
                        REQUIRE(std::isfinite(o[1]));
                        REQUIRE(std::isfinite(o[2]));
                        CHECK(got.velocity[i] == p.velocity[got.id[i]]);  // v_wall stays the wall's
                        const auto& v_wall = got.velocity[i];
                        moving += v_wall[0] != 0.0f;
                        const auto ref = test::reference_ghost_velocity(p, s, sp, got.position[i], by_id[got.id[i]]);
                        if (ref.det != 0 && std::abs(std::abs(ref.det) - CLSPH_MDBC_DET) < 0.02 * CLSPH_MDBC_DET) {
                            ++skipped;  // float and double may take different branches this close to the threshold
                            continue;
                        }
                        // The ghost node may leave the domain (random offsets): the kernel then sees
                        // no fluid, and neither does the reference, all of whose fluid is inside.
                        (!ref.fluid ? none : std::abs(ref.det) >= CLSPH_MDBC_DET ? corrected : shepard)++;
                        double err = 0;
                        for (int k = 0; k < 3; ++k) {
                            const double want = ref.fluid ? v_wall[k] - ref.v[k] : 0.0;
                            err = std::max(err, std::abs(o[k] - want));
                        }
                        worst = std::max(worst, err);
                        const bool ok = err <= 1e-3;  // m/s, against velocities up to 1 m/s (float sums)
                        if (!ok && wrong < 5)
                            MESSAGE("boundary id " << got.id[i] << ": device " << o[0] << ", " << o[1] << ", " << o[2]
                                                   << "; CPU v_G " << ref.v[0] << ", " << ref.v[1] << ", " << ref.v[2]
                                                   << " (det " << ref.det << ")");
                        wrong += !ok;
                        if (linear && ref.fluid && std::abs(ref.det) >= CLSPH_MDBC_DET) {
                            // First order reproduces a linear field at the node.
                            const auto& x = got.position[i];
                            const auto& m = by_id[got.id[i]];
                            const auto f = linear_field({x[0] + m[0], x[1] + m[1], x[2] + m[2]});
                            for (int k = 0; k < 3; ++k) {
                                CHECK(std::abs(ref.v[k] - f[k]) < 1e-6);
                                CHECK(std::abs(v_wall[k] - o[k] - f[k]) < 1e-3);  // the device's v_G
                            }
                            ++linear_checked;
                        }
                    }
                    MESSAGE((got.size() - fluid_n) << " boundary particles (" << moving << " moving): " << corrected
                                                 << " corrected, " << shepard << " Shepard, " << none << " without fluid, "
                                                 << skipped << " near the threshold; largest error " << worst << " m/s");
                    CHECK(wrong == 0);
                    if (fluid_n == 0) CHECK(none == got.size() - skipped);
                    if (fluid_n >= 3000) {
                        CHECK(corrected > 100);  // every branch was exercised
                        CHECK(none > 0);
                        CHECK(moving > 0);
                        if (linear) CHECK(linear_checked > 100);
                    }
                    if (fluid_n > 0 && fluid_n < 3) CHECK(corrected == 0);
                }
        }
    }
}
}
