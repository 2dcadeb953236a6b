#include "run_plan.hpp"

#include "run_record.hpp"

#include <clsph/error.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

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
    if (!(plan.until >= 0.0)) throw Error("--until: expected a simulated time >= 0 s");
    if (!(plan.every > 0.0) || !std::isfinite(plan.every))
        throw Error(args.every ? "--every: expected a time > 0 s" : "the scene's run.output_every must be > 0 s");
    if (args.steps && *args.steps == 0) throw Error("--steps: expected at least 1 step");
    if (std::isfinite(plan.until) && plan.until / plan.every > 1e6)
        throw Error("--every " + std::to_string(plan.every) + " s would write more than a million frames up to t = " +
                    std::to_string(plan.until) + " s; choose a larger --every");
    plan.out_dir = args.out ? *args.out : "out/" + std::filesystem::path(args.scene_path).stem().string();
    if (plan.out_dir.empty()) throw Error("--out: expected a directory");
    plan.collection_name = RunRecord::safe_name(scene.name) + ".pvd";
    return plan;
}

}  // namespace clsph::app
