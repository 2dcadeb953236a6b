// The facade behind clsph::Simulation (clsph/simulation.hpp): each call handed to the part that
// does it (simulation/impl.hpp lists them).
#include "simulation/impl.hpp"

#include "clsph/version.hpp"

#include <limits>

namespace clsph {

BalanceMode balance_mode_from_name(const std::string& name) {
    if (name == "dynamic") return BalanceMode::dynamic;
    if (name == "static") return BalanceMode::fixed;
    if (name == "off") return BalanceMode::off;
    throw Error("unknown balance mode '" + name + "' (use dynamic, static or off)");
}

Simulation::Simulation(const Scene& scene, const Options& options)
    : impl_(std::make_unique<Impl>(scene, options,
                                   [&](const device::Grid&) { return simulation::Source::from_scene(scene, options); })) {}

Simulation::Simulation(const Scene& scene, const Particles& p, const Options& options)
    : impl_(std::make_unique<Impl>(scene, options, [&](const device::Grid&) { return simulation::Source::from_particles(p); })) {}

Simulation::Simulation(const Scene& scene, const Checkpoint& c, const Options& options)
    : impl_(std::make_unique<Impl>(scene, options, [&](const device::Grid& grid) {
          return simulation::Source::from_checkpoint(scene, grid, c);
      })) {}

Simulation::~Simulation() = default;

const StepInfo& Simulation::step() {
    if (impl_->ahead.on())
        impl_->ahead.run(std::numeric_limits<double>::infinity(), {}, 1);
    else
        impl_->runner.step();
    return impl_->state.info;
}

void Simulation::run_until(double t, const std::function<void(const StepInfo&)>& on_step) {
    if (impl_->ahead.on())
        impl_->ahead.run(t, on_step, 0);
    else
        impl_->runner.run_until(t, on_step);
}

Checkpoint Simulation::checkpoint() {
    auto& m = *impl_;
    if (!m.ahead.idle())
        throw Error("checkpoint(): steps run ahead of the host; save after run_until returns, not in the step callback");
    m.ahead.drop_left();
    const auto& info = m.state.info;
    Checkpoint c;
    c.clsph_version = version();
    c.scene_hash = scene_hash(m.scene);
    c.step = info.step;
    c.time = info.time;
    c.dt = info.dt;
    c.dt_next = m.state.dt_next;
    c.removed = info.removed;
    c.created = info.created;
    c.inlet_next_id = m.driver.inlet_state().next_id;
    c.inlet_layers = m.driver.inlet_state().last_layer;
    c.fluid = info.fluid;
    c.cells = info.cells;
    c.kinetic_energy = info.kinetic_energy;
    c.max_speed = info.max_speed;
    for (auto cut : m.driver.cuts()) c.cuts.push_back(cut);
    cl_rt::guarded("reading the checkpoint", "", [&] {
        m.driver.save_owned(c);  // across ranks every rank takes part
        return 0;
    });
    return c;
}

void Simulation::save(const std::string& path) {
    const Checkpoint c = checkpoint();
    if (impl_->driver.writes_shared_files()) write_checkpoint(path, c);
}

Particles Simulation::particles() { return impl_->downloads.all(); }
std::vector<Particles> Simulation::particles_by_device(const Selection& which) { return impl_->downloads.by_device(which); }
Particles Simulation::particles(const Selection& which) { return impl_->downloads.selected(which); }
const Particles& Simulation::last_good() const { return impl_->downloads.last_good(); }

bool Simulation::steps_ahead() const { return impl_->ahead.on(); }
std::uint64_t Simulation::steps_taken_ahead() const { return impl_->ahead.taken(); }
std::uint64_t Simulation::steps_thrown_ahead() const { return impl_->ahead.thrown(); }
const StepInfo& Simulation::info() const { return impl_->state.info; }
double Simulation::time() const { return impl_->state.info.time; }
const Scene& Simulation::scene() const { return impl_->scene; }

}  // namespace clsph
