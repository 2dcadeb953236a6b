#include "simulation/step_runner.hpp"

#include "cl/errors.hpp"

#include <algorithm>

namespace clsph::simulation {

void StepRunner::step() {
    const double dt = state_.dt_next;
    multi::StepOutcome k;
    try {
        k = cl_rt::guarded("taking a step", "", [&] { return driver_.step(dt, state_.info.time); });
    } catch (const DeviceError& e) {
        failures_.device_failed(e, dt);
    }
    if (k.kick.bad_index >= 0) failures_.bad_particle(k);
    auto& info = state_.info;
    info.step += 1;
    info.time += dt;
    info.dt = dt;
    state_.take(k, driver_);
    state_.stamp_wall_time();
    state_.dt_next = next_dt(scene_, driver_.params(), k.kick);
    failures_.check_dt_collapse();
}

void StepRunner::run_until(double t, const std::function<void(const StepInfo&)>& on_step) {
    while (state_.info.time < t - 1e-12) {
        // Land on t exactly rather than overshooting it by most of a step.
        state_.dt_next = std::min(state_.dt_next, std::max(t - state_.info.time, 1e-12));
        step();
        if (on_step) on_step(state_.info);
    }
}

}  // namespace clsph::simulation
