// The resolved plan of a run: the command-line options over the scene's run control, checked.
#pragma once
#include "run_args.hpp"

#include <clsph/scene.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace clsph::app {

struct RunPlan {
    double until = 0.0;                       // simulated seconds (infinite: only --steps bounds the run)
    double every = 0.0;                       // simulated seconds between frames
    std::optional<std::uint64_t> steps;
    std::string out_dir;
    std::string collection_name;              // "<scene name>.pvd"
    // Frames the run writes if it reaches `until` (frame 0 included); 0 when unbounded.
    std::uint64_t expected_frames() const;
};

// Throws clsph::Error naming the option when a value is unusable (--every 0, --until -1).
RunPlan make_plan(const RunArgs& args, const Scene& scene);

}  // namespace clsph::app
