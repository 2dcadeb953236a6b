// Setting up the devices for a scene read from a file. Some scene checks only happen here (the
// grid: a periodic axis too short for the kernel support), and their messages name the key but
// not the file; this names the file too, as every other scene error does.
#pragma once
#include "run_args.hpp"

#include <clsph/simulation.hpp>

#include <memory>

namespace clsph::app {

std::unique_ptr<Simulation> make_simulation(const Scene& scene, const RunArgs& args);

}  // namespace clsph::app
