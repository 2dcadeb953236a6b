// Set-up: the devices opened (after the memory plan says the scene fits), the slab driver built
// from what the particles come from, and its first pass (the checks, reductions and a_0).
#pragma once
#include "cl/device.hpp"
#include "clsph/checkpoint.hpp"
#include "clsph/options.hpp"
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "multi/slab_driver.hpp"
#include "scene/lattice_plan.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace clsph::simulation {

// What the particles come from: the scene's lattice plan (each device generates its slab), a set
// of particles (built on the host, a frame read back, or a checkpoint's, decoded), and with a
// checkpoint its cuts, arrays and counters.
struct Source {
    std::optional<scene::LatticePlan> plan;
    Particles particles;               // without a plan
    const Checkpoint* checkpoint = nullptr;

    static Source from_scene(const Scene& scene, const Options& options);
    static Source from_particles(Particles p) { Source s; s.particles = std::move(p); return s; }
    // Throws CheckpointError when it was written for another scene.
    static Source from_checkpoint(const Scene& scene, const device::Grid& grid, const Checkpoint& c);
};

struct Opened {
    std::vector<std::unique_ptr<cl_rt::Device>> devices;
    std::unique_ptr<multi::SlabDriver> driver;
    multi::StepOutcome first;  // the first pass (dt = 0)
};

Opened open(const Scene& scene, const device::Grid& grid, const Options& options, const Source& source);

}  // namespace clsph::simulation
