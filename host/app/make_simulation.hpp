// Setting up the devices for a scene read from a file. Some scene checks only happen here (the
// grid: a periodic axis too short for the kernel support), and their messages name the key but
// not the file; this names the file too, as every other scene error does.
#pragma once
#include "run_args.hpp"

#include <clsph/error.hpp>
#include <clsph/simulation.hpp>

#include <memory>
#include <string>

namespace clsph {
struct Checkpoint;
}
namespace clsph::app {

// With a checkpoint: the run goes on from it (clsph resume); --steps counts from its step.
std::unique_ptr<Simulation> make_simulation(const Scene& scene, const RunArgs& args, const Checkpoint* checkpoint = nullptr);

// Runs f(); a SceneError whose message does not begin with the scene file gets it in front.
template <class F>
decltype(auto) with_scene_path(const RunArgs& args, F&& f) {
    try {
        return f();
    } catch (const SceneError& e) {
        const std::string message = e.what();
        if (message.compare(0, args.scene_path.size() + 1, args.scene_path + ":") == 0) throw;
        throw SceneError(args.scene_path + ": " + message);
    }
}

}  // namespace clsph::app
