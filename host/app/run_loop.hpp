// The stepping loop of `clsph run` and everything it writes as it goes: frames (in the
// background), stats, probes, checkpoints, surfaces, run.json, and the summary at the end.
#pragma once
#include "run_args.hpp"
#include "run_plan.hpp"
#include "run_record.hpp"

#include <clsph/io.hpp>
#include <clsph/simulation.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace clsph::app {

// clsph resume: where the run goes on from and what the output directory already holds.
struct ResumeState {
    ResumePoint point;
    std::vector<PvdEntry> frames;     // the collection as the run left it
    std::string start_time;           // the run's first start
    std::vector<std::string> resumes; // JSON objects, this one last
};

struct LoopEnd {
    int code = exit_ok;  // an ExitCode
    // With --on-device-failure continue, a device failed (code is exit_device_failed): its label
    // and the error, for the failover (resume.hpp); both empty otherwise. Across ranks the label
    // is empty on the ranks that gave up the step for another rank's device (the message says).
    std::string failed_device;
    std::string failure_message;
    bool failed() const { return !failure_message.empty(); }
};

// Steps `sim` from where it stands to the plan's end, or from the checkpoint `resume` names (null:
// a fresh start). `start`: when the command began (the summary's set-up time runs from it). A
// writer or I/O error is thrown (clsph::Error) once run.json says so.
LoopEnd run_loop(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* resume,
                 std::chrono::steady_clock::time_point start);

}  // namespace clsph::app
