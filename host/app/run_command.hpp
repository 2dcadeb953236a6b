// `clsph run SCENE` (and `clsph resume DIR`, whose command line is the run's): the start-up.
// Loads the scene and checks the plan, refuses an output directory in use, sets up the devices,
// and only then creates the directory and hands over to the run loop (run_loop.hpp) or, for a
// resume, to resume.hpp. Returns an ExitCode; throws clsph::Error for bad input (before anything
// is written).
#pragma once
#include "run_args.hpp"

namespace clsph::app {

int run_command(const RunArgs& args);

}  // namespace clsph::app
