// `clsph run --dry-run`: what a run would do and cost, without writing anything. The particle
// counts, grid and time-step figures come from the scene on the host; so does the memory plan
// (clsph/memory_plan.hpp): every device buffer, its bytes and bytes per particle, predicted per
// device without allocating, and the largest scene each device fits. Then the devices are set up
// (kernels built, particles uploaded, one step taken) to measure the engine's peak against the
// prediction, which also gives the real first time step. Nothing touches the output directory. A
// scene that does not fit stops after the plan, with the error a run would give.
#pragma once
#include "run_args.hpp"
#include "run_plan.hpp"

#include <clsph/scene.hpp>

namespace clsph::app {

int dry_run(const Scene& scene, const RunArgs& args, const RunPlan& plan);

}  // namespace clsph::app
