// mDBC's CPU form (kernels/mdbc.cl, mdbc_boundary_lanes: a work-item per cell, its boundary
// particles in vector lanes) against the fine form (mdbc_boundary, a work-item per particle) on
// every device, on random inputs: ghost nodes in many cells around each cell (the lanes share the
// union of their rows), some outside the domain, cells of more boundary particles than lanes, a
// periodic axis narrow enough that the union would wrap onto itself (the fine fallback).
#include "device/cell_pipeline.hpp"
#include "device/physics.hpp"
#include "support/mdbc_reference.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace clsph;
using namespace clsph::device;

namespace {

Scene box_scene(double dp, double y_max) {
    Scene s;
    s.physics.dp = dp;
    s.physics.c0 = 20.0;
    s.boundary_method = BoundaryMethod::mdbc;
    s.domain.min = {-0.1, 0.0, -0.1};
    s.domain.max = {0.4, y_max, 0.3};
    return s;
}

}  // namespace

TEST_SUITE("mdbc") {
TEST_CASE("mdbc CPU form (lanes) against the fine form on every device, random ghost nodes") {
    const double dp = 0.02;
    for (const bool periodic : {false, true}) {
        CAPTURE(periodic);
        // Periodic along y over 12 dp (three supports, the least a periodic axis may be): 6 cells at
        // reach 2, so a batch whose ghost nodes spread over 2 cells along y would meet itself across the wrap.
        Scene s = box_scene(dp, periodic ? 12 * dp : 0.3);
        s.domain.periodic = {false, periodic, false};
        Grid grid(Box{s.domain.min, s.domain.max}, s.physics.support(), 0, s.domain.periodic,
                  reach_for(s.physics.support(), dp));
        const int ny = periodic ? 12 : 11;
        for (auto* d : test::devices()) {
            CAPTURE(d->label());
            auto gen = test::rng(periodic ? 4711 : 4712);
            Physics fine(*d, grid, s, Interaction::fine);
            Physics lanes(*d, grid, s, Interaction::lanes);
            REQUIRE(lanes.interaction() == Interaction::lanes);
            const SphParams sp = fine.params();
            CellPipeline cells(*d, grid);
            for (std::size_t fluid_n : {std::size_t{0}, std::size_t{5}, std::size_t{3000}}) {
                CAPTURE(fluid_n);
                std::uniform_real_distribution<double> ux(0.0, 0.3), uy(0.0, ny * dp - 1e-6), uz(0.5 * dp, 8 * dp),
                    rho(990.0, 1010.0), mir(-6 * dp, 6 * dp);
                Particles p;
                std::vector<std::array<float, 3>> by_id;
                const float nan = std::numeric_limits<float>::quiet_NaN();  // must be overwritten
                for (int i = 0; i <= 15; ++i)
                    for (int j = 0; j < ny; ++j)
                        for (int l = 0; l < 3; ++l) {
                            std::array<float, 3> m{0.0f, 0.0f, static_cast<float>((2 * l + 1) * dp)};
                            if (gen() % 3 == 0) m = {float(mir(gen)), float(mir(gen)), float(std::abs(mir(gen)))};
                            by_id.push_back(m);
                            p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::boundary,
                                        {i * dp, j * dp, -l * dp}, {0, 0, 0}, nan, 0.0f);
                        }
                for (std::size_t k = 0; k < fluid_n; ++k)
                    p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, {ux(gen), uy(gen), uz(gen)},
                                {0, 0, 0}, static_cast<float>(rho(gen)), 0.0f);
                Particles got[2];
                for (int f = 0; f < 2; ++f) {
                    Physics& phys = f == 0 ? fine : lanes;
                    phys.set_ghost_nodes(by_id);
                    ParticleStore ps(*d, grid, p.size());
                    ps.upload(p);
                    cells.run(ps);
                    phys.boundary_densities(ps, cells);
                    got[f] = ps.download();
                    REQUIRE(got[f].size() == p.size());
                }
                std::size_t boundary = 0, equal = 0, wrong = 0, skipped = 0;
                double worst = 0;
                for (std::size_t i = 0; i < got[0].size(); ++i) {
                    REQUIRE(got[0].id[i] == got[1].id[i]);  // the same tables
                    if (got[0].type[i] == ParticleType::fluid) {
                        CHECK(got[1].density[i] == p.density[got[1].id[i]]);  // fluid densities are only read
                        continue;
                    }
                    ++boundary;
                    const float a = got[0].density[i], b = got[1].density[i];
                    REQUIRE(std::isfinite(a));
                    CHECK(std::isfinite(b));  // written (the poison is NaN)
                    if (a == b) {
                        ++equal;
                        continue;
                    }
                    // The forms add the same terms in the same order, but a CPU compiler may fuse
                    // multiply-adds differently in vectors and scalars: round-off, and near the
                    // determinant's threshold the two may take different branches.
                    const auto ref = test::reference_density(p, s, sp, got[0].position[i], by_id[got[0].id[i]]);
                    if (ref.det != 0 && std::abs(std::abs(ref.det) - CLSPH_MDBC_DET) < 0.02 * CLSPH_MDBC_DET) {
                        ++skipped;
                        continue;
                    }
                    worst = std::max(worst, double(std::abs(a - b)));
                    const bool ok = std::abs(a - b) <= 1e-3f * sp.rho0 * 1e-3f;  // 1e-6 rho0
                    if (!ok && wrong < 5)
                        MESSAGE("boundary id " << got[0].id[i] << ": fine " << a << ", lanes " << b << " (det " << ref.det << ")");
                    wrong += !ok;
                }
                MESSAGE(boundary << " boundary particles: " << equal << " bitwise equal, " << skipped
                                 << " near the threshold, largest difference " << worst << " kg/m^3");
                CHECK(boundary > 0);
                CHECK(wrong == 0);
            }
        }
    }
}
}
