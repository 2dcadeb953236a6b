// The synchronous step: the host waits for every step, so the state is the last step's whenever
// control is back with the caller (Options::synchronous, and every run the step ahead cannot take).
#pragma once
#include "multi/slab_driver.hpp"
#include "simulation/failures.hpp"
#include "simulation/run_state.hpp"

#include <functional>

namespace clsph::simulation {

class StepRunner {
public:
    StepRunner(const Scene& scene, multi::SlabDriver& driver, RunState& state, const Failures& failures)
        : scene_(scene), driver_(driver), state_(state), failures_(failures) {}
    void step();
    // Steps until simulated time t, landing on it exactly; the callback sees every step.
    void run_until(double t, const std::function<void(const StepInfo&)>& on_step);

private:
    const Scene& scene_;
    multi::SlabDriver& driver_;
    RunState& state_;
    const Failures& failures_;
};

}  // namespace clsph::simulation
