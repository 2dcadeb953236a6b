// What a run will allocate on each device, predicted on the host without allocating anything: the
// memory model behind `clsph run --dry-run` and the check that stops a run whose scene cannot fit
// before its first buffer is made. Every device buffer the engine allocates is listed here under
// the name the engine's memory tracker gives it (MemoryReport::peak_buffers measures the same),
// sized by the same rules as the allocations (device/particle_store.cpp, cell_pipeline.cpp,
// physics.cpp, the sort and scan temporaries, the exchange's boxes). No OpenCL here.
#pragma once
#include "clsph/devices.hpp"
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "clsph/options.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace clsph {

struct PlannedBuffer {
    std::string name;       // as the engine names it ("particles: positions", "neighbour ranges", ...)
    std::size_t bytes = 0;  // on this device, for this scene
    // Grows with the particle count (particle arrays, sort temporaries, cell tables: cells follow
    // the particles at a fixed dp); false: the same whatever dp (flags, reductions, probe points).
    bool scales = true;
};

struct DeviceMemoryPlan {
    DeviceInfo device;
    // A device runs several slabs (each its own buffers, the balancer cutting between them as
    // between devices) when one slab's largest buffer would exceed CL_DEVICE_MAX_MEM_ALLOC_SIZE:
    // this entry is slab `slab` of the device's `slabs` (MemoryPlan::devices holds them in a row).
    std::size_t slab = 0, slabs = 1;
    std::size_t particles = 0;  // owned at the start
    std::size_t capacity = 0;   // particles the arrays hold (the engine's sizing rule)
    std::size_t cells = 0;      // non-empty cells at the start (the cell tables' size)
    std::vector<PlannedBuffer> buffers;

    std::size_t total_bytes() const;
    std::size_t scaling_bytes() const;  // of buffers that grow with the particle count
    std::size_t fixed_bytes() const { return total_bytes() - scaling_bytes(); }
    const PlannedBuffer& largest() const;
    // Its largest buffer within CL_DEVICE_MAX_MEM_ALLOC_SIZE and its total within
    // CL_DEVICE_GLOBAL_MEM_SIZE (a limit of 0: not known). A device of several slabs must also fit
    // them all together: MemoryPlan::fits().
    bool fits() const;
};

struct MemoryPlan {
    std::size_t particles = 0;  // the scene's
    // The particles the stores are planned for: the scene's, and with inlets what they may add
    // (their buffers and as many layers as fill the domain once along each inlet's axis).
    std::size_t planned = 0;
    double dp = 0;              // the scene's physics.dp
    std::vector<DeviceMemoryPlan> devices;  // one per slab: a device of several slabs appears in a row
    // Caveats of this prediction for this run (several devices: the split is estimated, ...).
    std::vector<std::string> notes;
    // The interaction form the buffers are planned for: the one asked for (Options::interaction,
    // else the scene's run.interaction), except that `clusters`, whose lists would not fit, falls
    // back to `fine` (a note says so), which is what Simulation then runs.
    Interaction interaction = Interaction::automatic;

    // The most scene particles for which the device of entry d still fits its global memory (the
    // buffers of all its slabs that scale, scaled; the fixed ones kept; more slabs where a buffer
    // would outgrow one allocation); the whole selection: the least of these.
    std::size_t largest_particles(std::size_t entry) const;
    std::size_t largest_particles() const;
    // The dp that would give `n` particles for this scene's geometry (particle count ~ 1 / dp^3).
    double dp_for(std::size_t n) const;
    // Bytes the slabs of entry d's device need together.
    std::size_t device_bytes(std::size_t entry) const;
    // Slabs per selected device, in the selection's order (what the devices are opened as).
    std::vector<std::size_t> slabs_per_device() const;
    bool fits() const;
};

// The plan for `scene` with particles `p` on `devices` (in the selection's order) under `options`
// (capacity and cell headroom, the step ahead). A device whose slab would hold a buffer larger than
// its CL_DEVICE_MAX_MEM_ALLOC_SIZE is given as many slabs as keep every buffer within it (at most
// 64; a note says so), which is how Simulation opens it.
MemoryPlan plan_memory(const Scene& scene, const Particles& p, const std::vector<DeviceInfo>& devices,
                       const Options& options = {});

// The same for the scene's own particles, counted from its lattice without building them when set-up
// is on the devices (Options::setup_on_device, a scene without meshes), else built on the host.
MemoryPlan plan_memory(const Scene& scene, const std::vector<DeviceInfo>& devices, const Options& options = {});

// Throws SceneError naming physics.dp, each device's need and capacity, when `plan` does not fit.
void check_fits(const MemoryPlan& plan);

// The devices one run's chain of slabs spans, in chain order, as Simulation selects them from
// Options::devices: with Options::ranks every rank's own devices, gathered from every rank, rank
// 0's first (collective: every rank calls it), so every rank plans the whole chain alike; without,
// the selection. `rank`: the rank of each entry; [first, end): this rank's entries.
struct ChainDevices {
    std::vector<DeviceInfo> devices;
    std::vector<int> rank;
    std::size_t first = 0, end = 0;
};
ChainDevices chain_devices(const Options& options);

}  // namespace clsph
