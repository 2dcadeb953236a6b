// `clsph run --dry-run`: what a run would do and cost, without writing anything. The particle
// counts, grid and time-step figures come from the scene on the host; the memory per device is
// measured by setting the devices up (kernels built, particles uploaded) and taking one step,
// which also gives the real first time step. Nothing touches the output directory.
#pragma once
#include "run_args.hpp"
#include "run_plan.hpp"

#include <clsph/scene.hpp>

namespace clsph::app {

int dry_run(const Scene& scene, const RunArgs& args, const RunPlan& plan);

}  // namespace clsph::app
