#include "run_plan.hpp"

#include "frame_filter.hpp"
#include "run_record.hpp"

#include <clsph/error.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace clsph::app {

std::uint64_t RunPlan::expected_frames() const {
    if (!std::isfinite(until)) return 0;
    const double intervals = until / every;
    const double whole = std::floor(intervals + 1e-9);
    // Frame 0, one per whole interval, and a final frame at `until` when it is not on the grid.
    return 1 + static_cast<std::uint64_t>(whole) + (intervals - whole > 1e-9 ? 1 : 0);
}

RunPlan make_plan(const RunArgs& args, const Scene& scene) {
    RunPlan plan;
    // --steps alone runs that many steps; --until alone (or neither) runs to a simulated time.
    plan.until = args.until ? *args.until
                 : args.steps ? std::numeric_limits<double>::infinity()
                              : scene.run.end_time;
    plan.every = args.every.value_or(scene.run.output_every);
    plan.steps = args.steps;
    // Each value is named by where it came from: the option, or the scene key.
    const std::string until_name = args.until ? "--until" : "run.end_time";
    const std::string every_name = args.every ? "--every" : args.scene_path + ": run.output_every";
    if (args.until && !(std::isfinite(*args.until) && *args.until >= 0.0))
        throw Error("--until: expected a finite simulated time >= 0 s");
    if (!(plan.every > 0.0) || !std::isfinite(plan.every)) throw Error(every_name + ": expected a finite time > 0 s");
    FrameFilter::from_options(args.output_stride, args.output_box, args.fields);  // checked before anything is set up
    if (args.steps && (*args.steps == 0 || *args.steps > max_steps))
        throw Error("--steps: expected 1 to " + std::to_string(max_steps) + " steps");
    if (std::isfinite(plan.until) && plan.until / plan.every > 1e6) {
        std::ostringstream o;
        o << every_name << ": " << plan.every << " s would write more than a million frames up to " << until_name
          << " = " << plan.until << " s; choose a larger " << (args.every ? "--every" : "run.output_every") << " or a smaller "
          << (args.until ? "--until" : "run.end_time");
        throw Error(o.str());
    }
    plan.out_dir = args.out ? *args.out : "out/" + std::filesystem::path(args.scene_path).stem().string();
    if (plan.out_dir.empty()) throw Error("--out: expected a directory");
    plan.collection_name = RunRecord::safe_name(scene.name) + ".pvd";
    return plan;
}

}  // namespace clsph::app
