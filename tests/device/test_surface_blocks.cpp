// The free surface's device passes (kernels/surface.cl) against plain C++ on every device, on a
// random cloud: a tank's fluid jittered, thinned at random and sprayed with random particles, so
// there are full blocks inside, blocks at the surface and lone drops. The active blocks equal the
// reference's set; the field of a block equals the probes' (the per-point path) within round-off.
#include "clsph/scene.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"
#include "surface/device_surface.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace clsph;
using namespace clsph::surface;

namespace {

Particles random_cloud(const Scene& scene, std::mt19937_64& rng) {
    const Particles base = scene.build_particles();
    const double dp = scene.physics.dp;
    std::uniform_real_distribution<double> jitter(-0.2 * dp, 0.2 * dp), u(0, 1);
    Particles p;
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < base.size(); ++i) {
        const bool fluid = base.type[i] == ParticleType::fluid;
        if (fluid && base.position[i][2] > 0.12 && u(rng) < 0.05) continue;  // holes in the upper part
        auto x = base.position[i];
        if (fluid)  // off the lattice by a quarter spacing, then jittered: never across a block face
            for (auto& c : x) c += 0.25 * dp + jitter(rng);
        p.push_back(id++, base.type[i], x, {0, 0, 0}, base.density[i], 0);
    }
    for (int k = 0; k < 300; ++k) {  // spray over the tank
        const std::array<double, 3> x{0.3 * u(rng), 0.3 * u(rng), 0.2 + 0.1 * u(rng)};
        p.push_back(id++, ParticleType::fluid, x, {0, 0, 0}, static_cast<float>(scene.physics.rho0), 0);
    }
    return p;
}

BlockLattice lattice_of(const Scene& scene) {
    BlockLattice L;
    L.spacing = 0.5 * scene.physics.dp;
    for (std::size_t a = 0; a < 3; ++a) {
        L.origin[a] = scene.domain.min[a];
        L.blocks[a] = static_cast<std::uint32_t>(std::ceil((scene.domain.max[a] - scene.domain.min[a]) / L.edge()) + 1);
    }
    return L;
}

// The field of the blocks in `slots` (indices into the active keys `want`) against the probes at
// the same sample points: the worst difference and the largest fraction seen.
std::pair<double, double> field_against_probes(DeviceSurface& s, device::Physics& phys, device::ParticleStore& ps,
                                               device::CellPipeline& cells, const BlockLattice& L,
                                               const std::vector<std::uint32_t>& want,
                                               const std::vector<std::size_t>& slots) {
    double worst = 0, largest = 0;
    for (const auto slot : slots) {
        const auto c = L.coords(want[slot]);
        std::vector<std::array<double, 3>> points;
        for (std::uint32_t z = 0; z < kBlockSamples; ++z)
            for (std::uint32_t y = 0; y < kBlockSamples; ++y)
                for (std::uint32_t x = 0; x < kBlockSamples; ++x)
                    points.push_back({L.origin[0] + L.spacing * (c[0] * kBlockCubes + x),
                                      L.origin[1] + L.spacing * (c[1] * kBlockCubes + y),
                                      L.origin[2] + L.spacing * (c[2] * kBlockCubes + z)});
        const auto ref = phys.probe(ps, cells, points);
        const auto got = s.read_block(slot);
        for (std::size_t q = 0; q < points.size(); ++q) {
            worst = std::max(worst, std::abs(double(got[q]) - double(ref[q][0])));
            largest = std::max(largest, double(ref[q][0]));
        }
    }
    return {worst, largest};
}

}  // namespace

TEST_SUITE("surface") {
TEST_CASE("the surface's active blocks and their field on the device, as plain C++ on a random cloud") {
    Scene scene = test::small_tank(0.3, 0.2);  // made 0.3 m wide, so that blocks inside are full
    scene.domain.max[1] = 0.34;
    scene.walls[0].max[1] = 0.3;
    scene.fluids[0].max[1] = 0.3;
    auto rng = test::rng(0x5e7face);
    const Particles particles = random_cloud(scene, rng);
    const BlockLattice L = lattice_of(scene);
    const auto full = static_cast<std::uint32_t>(std::ceil(0.9 * std::pow(L.edge() / scene.physics.dp, 3)));
    std::vector<std::array<double, 3>> fluid;
    for (std::size_t i = 0; i < particles.size(); ++i)
        if (particles.type[i] == ParticleType::fluid) fluid.push_back(particles.position[i]);
    const auto want = active_blocks_reference(fluid, L, full);
    MESSAGE(particles.size() << " particles, " << want.size() << " of " << L.count() << " blocks active");
    REQUIRE(want.size() > 20);
    // Full blocks inside are left out: fewer than the blocks with fluid in or next to them.
    const auto wet = active_blocks_reference(fluid, L, 0xffffffffu);
    MESSAGE((wet.size() - want.size()) << " blocks left out as inside");
    REQUIRE(want.size() < wet.size());

    device::Grid grid(device::Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, scene.domain.periodic);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        device::Physics phys(*d, grid, scene);
        device::CellPipeline cells(*d, grid);
        device::ParticleStore ps(*d, grid, particles.size());
        ps.upload(particles);
        cells.run(ps);
        // Capacity for a few blocks more than there are: the blocks past the live ones are zeros.
        DeviceSurface s(*d, grid, phys, L, SurfaceCapacity{want.size() + 7, 0, 0});
        s.count(ps);
        s.activate(full);
        REQUIRE(s.active_blocks(full) == want.size());
        CHECK(s.active_keys() == want);
        // Short of capacity: counted all the same, the capacity grown and the blocks compacted again.
        DeviceSurface short_of(*d, grid, phys, L, SurfaceCapacity{want.size() / 3, 0, 0});
        short_of.count(ps);
        short_of.activate(full);
        CHECK(short_of.active_blocks(full) == want.size());
        CHECK(short_of.capacity().blocks >= want.size());
        CHECK(short_of.active_keys() == want);

        // The field of a few blocks (the first, the last and random ones) against the probes.
        s.sample(ps, cells, 0, grid.params().n_s);
        const std::vector<float> poison(kBlockPoints, 7.0f);
        s.write_block(want.size() + 3, poison);  // a block past the live ones, poisoned, then sampled again
        s.sample(ps, cells, 0, grid.params().n_s);
        const auto dead = s.read_block(want.size() + 3);
        CHECK(std::all_of(dead.begin(), dead.end(), [](float v) { return v == 0.0f; }));
        std::vector<std::size_t> slots{0, want.size() - 1};
        std::uniform_int_distribution<std::size_t> pick(0, want.size() - 1);
        for (int k = 0; k < 6; ++k) slots.push_back(pick(rng));
        // And a block just under the water's top (z = 0.2), active and wet.
        const auto wet_key = static_cast<std::uint32_t>(
            std::floor((0.15 - L.origin[0]) / L.edge()) +
            L.blocks[0] * (std::floor((0.15 - L.origin[1]) / L.edge()) + L.blocks[1] * std::floor((0.19 - L.origin[2]) / L.edge())));
        const auto it = std::lower_bound(want.begin(), want.end(), wet_key);
        REQUIRE(it != want.end());
        REQUIRE(*it == wet_key);
        slots.push_back(static_cast<std::size_t>(it - want.begin()));
        const auto [worst, largest] = field_against_probes(s, phys, ps, cells, L, want, slots);
        MESSAGE("field of " << slots.size() << " blocks: largest fraction " << largest << ", worst difference " << worst);
        CHECK(largest > 0.5);
        CHECK(worst < 1e-4);
    }
}

TEST_CASE("a surface taken with capacities too small redoes and gives the same mesh, on every device") {
    Scene scene = test::small_tank(0.3, 0.2);
    auto rng = test::rng(0x5e7f0ce);
    const Particles particles = random_cloud(scene, rng);
    const BlockLattice L = lattice_of(scene);
    const auto full = static_cast<std::uint32_t>(std::ceil(0.9 * std::pow(L.edge() / scene.physics.dp, 3)));
    device::Grid grid(device::Box{scene.domain.min, scene.domain.max}, scene.physics.support(), 0, scene.domain.periodic);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        device::Physics phys(*d, grid, scene);
        device::CellPipeline cells(*d, grid);
        device::ParticleStore ps(*d, grid, particles.size());
        ps.upload(particles);
        cells.run(ps);
        auto take = [&](DeviceSurface& s) {
            int attempts = 0;
            do {
                ++attempts;
                REQUIRE(attempts <= 4);
                s.count(ps);
                s.activate(full);
                s.sample(ps, cells, 0, grid.params().n_s);
                s.mesh(0.5f);
            } while (!s.settle());
            return attempts;
        };
        DeviceSurface first(*d, grid, phys, L);  // no capacity at all: the first surface of a run
        CHECK(take(first) >= 2);
        DeviceSurface roomy(*d, grid, phys, L, first.capacity());
        REQUIRE(take(roomy) == 1);
        const MeshPart want = roomy.download();
        REQUIRE(want.triangles.size() > 1000);
        // A capacity short in each count in turn, then in all three.
        const SurfaceCapacity big = roomy.capacity();
        for (const SurfaceCapacity small : {SurfaceCapacity{3, big.vertices, big.triangles},
                                            SurfaceCapacity{big.blocks, want.positions.size() / 2, big.triangles},
                                            SurfaceCapacity{big.blocks, big.vertices, want.triangles.size() - 1},
                                            SurfaceCapacity{1, 1, 1}}) {
            DeviceSurface s(*d, grid, phys, L, small);
            const int attempts = take(s);
            MESSAGE("capacity " << small.blocks << "/" << small.vertices << "/" << small.triangles << ": " << attempts
                                << " attempts, then " << s.capacity().blocks << "/" << s.capacity().vertices << "/"
                                << s.capacity().triangles);
            CHECK(attempts >= 2);
            const MeshPart got = s.download();
            CHECK(got.positions == want.positions);
            CHECK(got.normals == want.normals);
            CHECK(got.edges == want.edges);
            CHECK(got.triangles == want.triangles);
            // Taken again with the grown capacities: no redo.
            CHECK(take(s) == 1);
        }
    }
}
}

TEST_SUITE("surface") {
TEST_CASE("the surface's field on kept cell tables (run.list_buffer): particles moved since the sort still counted, as the probes count them") {
    // Cells the buffer wider; every fluid particle moved in place (its offset from the cell it was
    // sorted into) by up to 0.45 of half the buffer, as kept tables hold them before the next build.
    // A block's rows must reach that much further than the support (kernels/surface.cl).
    Scene scene = test::small_tank(0.3, 0.2);
    scene.domain.max[1] = 0.34;
    scene.walls[0].max[1] = 0.3;
    scene.fluids[0].max[1] = 0.3;
    scene.run.list_buffer = 1.0;  // the largest: a move of up to 0.225 supports, which the kernel weighs
    auto rng = test::rng(0x5e7fac2);
    const Particles particles = random_cloud(scene, rng);
    const BlockLattice L = lattice_of(scene);
    const double support = scene.physics.support(), step = 0.45 * 0.5 * scene.run.list_buffer * support;
    device::Grid grid(device::Box{scene.domain.min, scene.domain.max}, support * (1 + scene.run.list_buffer), 0,
                      scene.domain.periodic);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        device::Physics phys(*d, grid, scene);
        device::CellPipeline cells(*d, grid);
        device::ParticleStore ps(*d, grid, particles.size());
        ps.upload(particles);
        cells.run(ps);
        const std::size_t n = ps.ranges.active();
        const Particles sorted = ps.download();
        std::vector<float> pos(4 * n);
        d->read(ps.pos, pos.data(), pos.size());
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (std::size_t i = 0; i < n; ++i) {
            if (sorted.type[i] != ParticleType::fluid) continue;
            std::array<double, 3> v{u(rng), u(rng), u(rng)};
            const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            for (int k = 0; k < 3; ++k) pos[4 * i + k] += static_cast<float>(v[k] * step / std::max(len, 1.0));
        }
        d->write(ps.pos, pos.data(), pos.size());
        std::vector<std::array<double, 3>> fluid;
        const Particles moved = ps.download();
        for (std::size_t i = 0; i < moved.size(); ++i)
            if (moved.type[i] == ParticleType::fluid) fluid.push_back(moved.position[i]);
        const auto full = static_cast<std::uint32_t>(std::ceil(0.9 * std::pow(L.edge() / scene.physics.dp, 3)));
        const auto want = active_blocks_reference(fluid, L, full);
        REQUIRE(want.size() > 20);
        DeviceSurface s(*d, grid, phys, L, SurfaceCapacity{want.size() + 7, 0, 0});
        s.count(ps);
        s.activate(full);
        REQUIRE(s.active_blocks(full) == want.size());
        s.sample(ps, cells, 0, grid.params().n_s);
        std::vector<std::size_t> slots(want.size());
        for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = k;
        const auto [worst, largest] = field_against_probes(s, phys, ps, cells, L, want, slots);
        MESSAGE("field of all " << want.size() << " active blocks: largest fraction " << largest << ", worst difference " << worst);
        CHECK(largest > 0.5);
        CHECK(worst < 1e-4);
    }
}
}
