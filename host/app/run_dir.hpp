// What the commands over a run's output directory (clsph surface, render, view) read from it:
// the resolved scene from run.json, and the frame collection (.pvd) clsph run writes.
#pragma once
#include <clsph/scene.hpp>

#include <string>

namespace clsph::app {

// The scene run.json holds; `command` names the command in the errors ("clsph surface").
Scene scene_of_run(const std::string& dir, const std::string& command);
// The run's frame collection (not surface.pvd); empty when there is none.
std::string frames_pvd(const std::string& dir);

}  // namespace clsph::app
