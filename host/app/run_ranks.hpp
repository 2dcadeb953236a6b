// What a run across MPI ranks does differently from one process, for every part of `clsph run`:
// which rank speaks, and the device list of the whole run.
#pragma once
#include "run_args.hpp"

#include <clsph/simulation.hpp>

#include <string>
#include <vector>

namespace clsph::app {

// Across MPI ranks: rank 0 speaks and writes the run's files; every rank writes its frame pieces.
bool speaks(const RunArgs& args);

// Every device of the run: this process's, or across ranks every rank's ("rank R: #i name").
// Across ranks every rank must call it (it gathers).
std::vector<std::string> all_device_names(const Simulation& sim, const RunArgs& args);

}  // namespace clsph::app
