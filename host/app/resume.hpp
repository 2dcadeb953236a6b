// Going on with a run: `clsph resume` (the newest checkpoint that reads back whole, the output
// directory as the run left it) and, with --on-device-failure continue, the failover to the
// devices left after one failed (the same resume, recorded in run.json's resumes with the reason).
#pragma once
#include "run_args.hpp"
#include "run_loop.hpp"
#include "run_plan.hpp"

#include <clsph/scene.hpp>
#include <clsph/simulation.hpp>

#include <chrono>

namespace clsph::app {

// The run loop on `sim` (from `resume`, null: a fresh start); when a device fails and
// --on-device-failure continue asks for it, resume_run on the devices left. Returns an ExitCode.
int run_with_failover(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* resume,
                      const Scene& scene, std::chrono::steady_clock::time_point start);

// clsph resume: the run's command line (resume_args.hpp) over its last checkpoint, in its directory.
int resume_run(const Scene& scene, const RunArgs& args, const RunPlan& plan, std::chrono::steady_clock::time_point start);

}  // namespace clsph::app
