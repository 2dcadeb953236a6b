// Running a scene on OpenCL devices: the facade a host program (and the clsph tool) uses.
#pragma once
#include "clsph/interaction.hpp"
#include "clsph/options.hpp"
#include "clsph/mesh.hpp"
#include "clsph/render.hpp"
#include "clsph/particles.hpp"
#include "clsph/ranks.hpp"
#include "clsph/scene.hpp"

#include <cstdint>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace clsph {
struct Checkpoint;  // clsph/checkpoint.hpp

struct DeviceShare {
    std::string device;
    std::size_t particles = 0;  // owned
    std::size_t first_column = 0, end_column = 0;
    double force_seconds = 0;   // the last step's force pass (several devices)
    std::size_t ghosts = 0;     // read-only copies of the neighbours' edge columns held now
    std::size_t received_bytes = 0;  // copied into this device from the others since the start
    // Force passes whose interior ran while the arrivals from the other devices travelled (the
    // halo overlapped with it: docs/multi_device.md), since the start.
    std::size_t split_force_passes = 0;
    // The calibration before the first step (several devices, dynamic balance; 0 otherwise): the
    // force pass this device would need for the whole scene, fitted as fixed + per-unit cost.
    double calibrated_whole_scene_seconds = 0;
    double calibrated_fixed_seconds = 0;
    Interaction interaction = Interaction::automatic;  // the interaction form this device runs
    CellOrder cell_order = CellOrder::automatic;       // the order within cells (the run's, on every device)
};

// The cell tables (and the clusters form's lists) of the run: built, each with a sort of every
// particle, once before the first step and then every step, or, with run.list_buffer, only when a
// particle may have moved half the buffer since the last build (docs/interaction.md).
struct TableBuilds {
    std::size_t builds = 0;   // since the start (the first included)
    std::size_t age = 0;      // steps since the last build
    double moved = 0;         // the most any particle can have moved since then, m (a bound)
};

struct StepInfo {
    std::uint64_t step = 0;
    double time = 0.0;         // simulated time after the step (s)
    double dt = 0.0;           // the step just taken (s)
    std::size_t particles = 0;
    std::size_t fluid = 0;
    std::size_t removed = 0;   // particles removed so far (left the domain: outlets, open faces)
    std::size_t created = 0;   // particles created so far (inlets: docs/scenes.md)
    double kinetic_energy = 0.0;  // J, fluid particles
    double max_speed = 0.0;    // m/s
    std::size_t cells = 0;     // non-empty grid cells after the step (one device; several: 0)
    double wall_seconds = 0.0; // since the run began
};

struct ProbeSample {
    std::string name;
    double time = 0.0;
    double value = 0.0;  // Pa for pressure probes, m for height probes (NaN: no fluid there)
};

// A floating body now (docs/scenes.md, floating): its state after the last step.
struct BodySample {
    std::string name;                        // the scene's floating.name (body_NAME.csv)
    double time = 0.0;
    std::array<double, 3> position{};        // the centre of mass (m)
    std::array<double, 4> quaternion{1, 0, 0, 0};  // orientation from rest (w, x, y, z)
    std::array<double, 3> velocity{}, angular_velocity{};  // m/s, rad/s
    std::array<double, 3> force{}, torque{};  // the fluid's, about the centre (N, N m; gravity not included)
    double mass = 0.0;                       // kg
};

struct KernelTime {
    std::string name;
    std::string device;  // the device that ran it (empty for host phases)
    std::size_t calls = 0;
    double seconds = 0.0;
};

// One command (kernel or transfer) on one device: its start and end on the device's own clock (ns;
// clocks of different devices are not comparable).
struct CommandSpan {
    std::string device;
    std::string name;
    std::uint64_t start_ns = 0, end_ns = 0;
};

struct MemoryReport {
    std::string device;
    std::size_t particles = 0;
    std::size_t peak_bytes = 0;      // the engine's own device allocations at their peak
    std::size_t capacity_particles = 0;
    // The buffers held when the peak was reached, bytes by name (clsph/memory_plan.hpp predicts
    // the same names).
    std::map<std::string, std::size_t> peak_buffers;
    double bytes_per_particle() const { return particles ? double(peak_bytes) / double(particles) : 0.0; }
};

// Which particles a thinned download keeps (Simulation::particles(const Selection&)).
struct ParticleSelection {
    std::uint32_t stride = 1;                    // ids divisible by it
    std::optional<std::array<double, 6>> box;    // xmin ymin zmin xmax ymax zmax, faces included
    bool all() const { return stride <= 1 && !box; }
};

class Simulation {
public:
    Simulation(const Scene& scene, const Options& options = {});
    // The scene's physics and domain with these particles instead of the scene's own (a frame read
    // back from disk, say); ids must be unique.
    Simulation(const Scene& scene, const Particles& particles, const Options& options = {});
    // Goes on from a checkpoint (read_checkpoint, clsph/checkpoint.hpp) of this scene: on the
    // device set it was written on (same count, same implementation), the steps that follow are
    // bitwise those the run would have taken; on another device set, the same particles with
    // positions within round-off. Throws CheckpointError when it was written for another scene.
    Simulation(const Scene& scene, const Checkpoint& checkpoint, const Options& options = {});
    ~Simulation();
    // The state now as a checkpoint, and written to `path` (docs/checkpoint.md; through a
    // temporary name and a rename). Not from inside the step callback while steps run ahead.
    // Across MPI ranks both are collective: every rank's particles are gathered to rank 0, whose
    // checkpoint holds them all and which writes the file; the others' hold no particles.
    Checkpoint checkpoint();
    void save(const std::string& path);
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    // One time step. Throws SimulationError (naming step, time, particle id) when a value goes
    // non-finite or a density leaves the configured band; last_good() then holds the last state
    // that passed the checks (taken at the last call of particles() or every checkpoint_every steps).
    const StepInfo& step();
    // Steps until simulated time t; the callback sees every step (return value ignored).
    void run_until(double t, const std::function<void(const StepInfo&)>& on_step = {});

    Particles particles();                   // host copy, pressure filled in
    // The particles whose id is divisible by `stride` and (with a box: xmin ymin zmin xmax ymax
    // zmax, faces included) inside it, selected on the devices: the others never reach the host
    // (a strided frame of a billion particles costs its own size). last_good() is left as it was.
    using Selection = ParticleSelection;
    Particles particles(const Selection& which);
    // The same, one part per device (in device_names() order): the particles each owns now,
    // downloaded by one thread per device. Without a selection, last_good() becomes their
    // concatenation.
    std::vector<Particles> particles_by_device(const Selection& which = {});
    const Particles& last_good() const;
    const StepInfo& info() const;
    double time() const;
    const Scene& scene() const;
    std::vector<std::string> device_names() const;
    std::vector<DeviceShare> shares() const;  // each device's part of the domain now
    // The order within cells the run resolved to (arrival or morton; the same on every device and
    // rank, also on a rank without devices).
    CellOrder cell_order() const;
    TableBuilds table_builds() const;

    // The floating bodies now, in the order of boundaries.boxes (empty: none).
    std::vector<BodySample> bodies() const;
    // Probe values now (computed on the device).
    std::vector<ProbeSample> sample_probes();
    // The free surface now (clsph/mesh.hpp): sampled and meshed on the devices, each its own slab;
    // the same mesh on any number of devices.
    TriangleMesh surface(const SurfaceOptions& options = {});
    // An image of `surface` (from surface()) with the scene's solid boxes and walls, seen by
    // `camera`: each device draws the triangles over its own slab, the host keeps the nearest.
    Image render(const TriangleMesh& surface, const CameraView& camera, const ImageStyle& style = {});
    // An image of the state now as the scene's render settings draw it, seen by `camera`: with
    // render.method "surface" the free surface made and drawn on the devices, nothing but the
    // images leaving them (render() of surface() draws the same picture); with "splat" the fluid
    // particles splatted and shaded in screen space, no mesh (docs/scenes.md, render; `style`
    // colours surfaces only). The one entry point for a picture of the running simulation (the
    // tool's frames, the live view, Python's sim.image).
    Image image(const CameraView& camera, const ImageStyle& style = {});
    // Across MPI ranks surface(), render() and image() are collective: every rank makes and draws
    // its own slabs; surface() returns the whole mesh on every rank, and the images go to rank 0,
    // which composes the picture: on the others render() and image() return an empty Image (its
    // range set).

    std::vector<KernelTime> profile();       // per-kernel totals since the start (Options::profile)
    std::vector<KernelTime> host_phases() const;  // host wall time per step phase
    std::vector<CommandSpan> take_trace();   // commands since the last call (Options::trace)
    // Whether steps run ahead of the host (Options::synchronous off, one device with cl_khr_fp64).
    bool steps_ahead() const;
    // How many of the steps since this Simulation was made ran ahead of the host; the others were
    // waited for (the steps that build the cell tables or exchange particles between devices, and
    // every step where steps_ahead() is false).
    std::uint64_t steps_taken_ahead() const;
    // Steps computed ahead of the host and thrown away since this Simulation was made: those in
    // flight behind a step that halted (the cell tables to be built, or grown) or past an event.
    // Their force passes cost time for nothing; the host enqueues no step past a build it foresees.
    std::uint64_t steps_thrown_ahead() const;
    std::vector<MemoryReport> memory() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace clsph
