#include "simulation/setup.hpp"

#include "cl/errors.hpp"
#include "clsph/memory_plan.hpp"
#include "clsph/testing.hpp"
#include "device/memory_census.hpp"
#include "device/particle_store.hpp"
#include "multi/ranks.hpp"
#include "simulation/chain_devices.hpp"

#include <algorithm>
#include <sstream>
#include <string>

namespace clsph::simulation {

namespace {

// A scene that asks for fluid (blocks, or meshes filled with fluid) whose fluid gives no particle
// at all: every block thinner than the lattice, say. It would run, empty, to completion.
void require_fluid(const Scene& scene, std::uint64_t fluid) {
    const bool asks = !scene.fluids.empty() ||
                      std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const MeshObject& m) { return m.fluid; });
    if (!asks || fluid > 0) return;
    std::ostringstream o;
    o << "fluid: the scene's fluid gives no particles at physics.dp = " << scene.physics.dp
      << " m (a fluid block needs room for at least one lattice point, dp/2 from its faces and away from the "
         "walls): make physics.dp smaller or the fluid blocks larger";
    throw SceneError(o.str());
}

}  // namespace

Source Source::from_scene(const Scene& scene, const Options& options) {
    Source s;
    if (options.setup_on_device && scene::LatticePlan::supports(scene)) {
        if (options.on_setup) options.on_setup("planning the particles of the scene");
        s.plan = scene::LatticePlan::make(scene);
    } else {
        if (options.on_setup) options.on_setup("building the particles of the scene on the host");
        s.particles = scene.build_particles();
    }
    require_fluid(scene, s.plan ? s.plan->fluid_count
                                : static_cast<std::uint64_t>(std::count(s.particles.type.begin(), s.particles.type.end(),
                                                                        ParticleType::fluid)));
    return s;
}

Source Source::from_checkpoint(const Scene& scene, const device::Grid& grid, const Checkpoint& c) {
    if (c.scene_hash != scene_hash(scene))
        throw CheckpointError("(in memory)", "written for another scene (its scene hash differs)");
    // The checkpoint's particles as the host holds them (the census and the split read positions).
    Source s = from_particles(device::decode_particles(grid, c.pos.data(), c.velrho.data(), c.id.data(), c.size()));
    s.checkpoint = &c;
    return s;
}

namespace {

cl_rt::EventSet::Mode wait_mode(WaitMode w) {
    using Mode = cl_rt::EventSet::Mode;
    return w == WaitMode::poll ? Mode::poll : w == WaitMode::block ? Mode::block : Mode::callbacks;
}

multi::DriverOptions driver_options(const Scene& scene, const Options& options, const Checkpoint* c,
                                    Interaction planned) {
    multi::DriverOptions d;
    d.interaction = options.interaction != Interaction::automatic ? options.interaction : scene.run.interaction;
    if (planned != Interaction::automatic) d.interaction = planned;  // the memory plan's fallback
    d.cell_order = options.cell_order != CellOrder::automatic ? options.cell_order : scene.run.cell_order;
    d.balance = options.balance == BalanceMode::dynamic ? balance::Mode::dynamic
                : options.balance == BalanceMode::fixed ? balance::Mode::static_
                                                        : balance::Mode::off;
    d.balance_log = options.balance_log;
    d.headroom = options.capacity_headroom;
    d.cell_headroom = options.cell_headroom;
    d.wait = wait_mode(options.wait);
    if (options.seams) d.seams = *options.seams;
    d.progress = options.on_setup;
    d.ranks = options.ranks;
    // A checkpoint's cuts, which the driver takes when they fit its slab count (every rank's slabs).
    if (c) d.cuts.assign(c->cuts.begin(), c->cuts.end());
    // Inlets: a checkpoint's feed, so the resumed run makes the same particles with the same ids.
    if (c && !scene.inlets.empty()) {
        const std::size_t streams = scene::inlet_streams(scene);  // one an inlet, or one per profile point
        if (c->inlet_layers.size() != streams)
            throw CheckpointError("(resume)", "holds no inlet state for the scene's " + std::to_string(scene.inlets.size()) +
                                                  " inlets (" + std::to_string(streams) + " streams)");
        d.inlet_state = scene::InletState{c->inlet_next_id, c->inlet_layers};
    }
    if (c) d.start_time = c->time;  // inlets, outlet zones: the first pass's time
    d.resumed = c != nullptr;
    return d;
}

}  // namespace

Opened open(const Scene& scene, const device::Grid& grid, const Options& options, const Source& source) {
    cl_rt::OpenOptions open{options.profile, options.seams ? options.seams->faults : std::vector<testing::Fault>{}};
    if (options.seams) open.max_allocation = options.seams->max_allocation;
    std::string spec = options.devices.empty() ? default_device_spec() : options.devices;
    const scene::LatticePlan* lattice = source.plan ? &*source.plan : nullptr;
    Interaction planned = Interaction::automatic;
    // The memory plan before any context or buffer, over the whole chain of slabs (across ranks
    // every rank's devices, gathered, so every rank plans alike and stops alike): a scene that
    // cannot fit stops here, and a device whose slab would hold a buffer above its largest
    // allocation is opened as several slabs.
    const ChainDevices chain = chain_devices(spec, open, options.ranks.get());
    const MemoryPlan plan = lattice ? detail::plan_memory(scene, detail::census_of(scene, *lattice), chain.devices, options)
                                    : plan_memory(scene, source.particles, chain.devices, options);
    check_fits(plan);
    const auto slabs = plan.slabs_per_device();
    open.slabs.assign(slabs.begin() + static_cast<std::ptrdiff_t>(chain.first), slabs.begin() + static_cast<std::ptrdiff_t>(chain.end));
    planned = plan.interaction;
    // Across ranks this rank opens its own devices (dealt from the node's, or its clause of a
    // per-rank spec).
    if (options.ranks) spec = rank_spec(spec, *options.ranks);
    Opened o;
    if (!options.ranks || !spec.empty()) o.devices = cl_rt::open_devices(spec, open);  // across ranks a rank may drive none
    std::vector<cl_rt::Device*> devs;
    for (auto& d : o.devices) {
        d->profiler().enable(options.profile);
        d->profiler().trace(options.profile && options.trace);
        devs.push_back(d.get());
    }
    const auto dopt = driver_options(scene, options, source.checkpoint, planned);
    // An OpenCL call that throws outside the runtime's wrappers is a DeviceError too.
    o.first = cl_rt::guarded("setting up the devices", "", [&] {
        o.driver = lattice ? std::make_unique<multi::SlabDriver>(devs, grid, scene, *lattice, dopt)
                           : std::make_unique<multi::SlabDriver>(devs, grid, scene, source.particles, dopt);
        return o.driver->start();  // dt = 0: the checks, reductions and a_0 into accel
    });
    return o;
}

}  // namespace clsph::simulation
