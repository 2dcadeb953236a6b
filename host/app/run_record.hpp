// The small per-run files beside the frames: stats.csv (one row per step), probe_<name>.csv (one
// row per probe sample) and run.json (provenance: the resolved scene, version, devices, command
// line, start time, and how the run ended). These are short text rows written on the main thread
// into buffered streams, far cheaper than a step; the frames go through FrameWriter.
#pragma once
#include <clsph/simulation.hpp>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace clsph::app {

struct RunIdentity {
    std::string scene_file;
    std::vector<std::string> overrides;
    std::vector<std::string> command_line;
    std::vector<std::string> devices;
    std::vector<std::string> interactions;  // the interaction form each device runs, in device order
    std::string scene_json;  // Scene::to_json(): the resolved scene, every default filled in
};

class RunRecord {
public:
    RunRecord(std::string dir, RunIdentity identity, const std::vector<Probe>& probes);

    // stats.csv: step,time,dt,particles,fluid,removed,kinetic_energy,max_speed. The files are
    // flushed about once a second, so `tail -f` and a plotting script see the run as it goes.
    void step(const StepInfo& s);
    // probe_<name>.csv: time,value (NaN: no fluid at the probe)
    void probes(const std::vector<ProbeSample>& samples);
    // Rewrites run.json with the outcome ("running", "completed", "interrupted", "failed") and the
    // last step reached; flushes the CSV streams so they are complete whatever happens next.
    void finish(const std::string& status, const StepInfo& last, const std::string& message = {});

    // A file-name-safe form of a probe or scene name ("p wall/1" -> "p_wall_1").
    static std::string safe_name(const std::string& name);

private:
    void write_json(const std::string& status, const StepInfo* last, const std::string& message) const;

    std::string dir_;
    RunIdentity identity_;
    std::string started_;  // ISO 8601 UTC
    std::ofstream stats_;
    std::chrono::steady_clock::time_point last_flush_;
    std::vector<std::pair<std::string, std::unique_ptr<std::ofstream>>> probe_files_;  // by probe name
};

}  // namespace clsph::app
