// `clsph run SCENE`: load the scene, set up the devices, then create the output directory and
// step, writing frames in the background, stats and probes as the run goes, and a summary at the
// end. Returns an ExitCode; throws clsph::Error for bad input (before anything is written).
#pragma once
#include "run_args.hpp"

namespace clsph::app {

int run_command(const RunArgs& args);

}  // namespace clsph::app
