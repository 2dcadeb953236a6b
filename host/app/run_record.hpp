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

// Now as ISO 8601 UTC text, e.g. 2026-12-01T18:00:00Z (run.json's times).
std::string utc_now();

struct RunIdentity {
    std::string scene_file;
    std::vector<std::string> overrides;
    std::vector<std::string> command_line;
    std::vector<std::string> devices;
    std::vector<std::string> interactions;  // the interaction form each device runs, in device order
    std::string cell_order;                 // the order within cells (the run's: arrival or morton; empty: not known)
    std::string scene_json;  // Scene::to_json(): the resolved scene, every default filled in
    // clsph resume: the run's first start time and the resumes so far, each a JSON object.
    std::string start_time;
    std::vector<std::string> resumes;
};

// A resume's rows: stats.csv rows after `step` and probe rows after `time` are cut off (a run
// killed after its last checkpoint wrote them; they are written again), the rest kept.
struct ResumePoint {
    std::uint64_t step = 0;
    double time = 0;
};

class RunRecord {
public:
    // `writes` false: a record that writes nothing (the ranks of an MPI run other than rank 0).
    RunRecord(std::string dir, RunIdentity identity, const std::vector<Probe>& probes, const ResumePoint* resume = nullptr,
              bool writes = true);

    // stats.csv: step,time,dt,particles,fluid,removed,kinetic_energy,max_speed. The files are
    // flushed about once a second, so `tail -f` and a plotting script see the run as it goes, and
    // at every frame (flush()).
    void step(const StepInfo& s);
    // Pushes the CSV rows so far to the files (the run loop calls it at every frame, so what a
    // kill -9 leaves is complete up to the last frame listed in the .pvd).
    void flush();
    // probe_<name>.csv: time,value (NaN: no fluid at the probe)
    void probes(const std::vector<ProbeSample>& samples);
    // Floating bodies (Simulation::bodies): a row in each body_NAME.csv (opened at the first call;
    // on a resume, kept up to the checkpoint's time), and the last state for run.json.
    void bodies(const std::vector<BodySample>& samples);
    // run.list_buffer > 0: the cell tables' builds since this process started, for run.json
    // ("table_builds"; none otherwise).
    void table_builds(std::size_t builds) { table_builds_ = builds; }
    // Of this process's steps, those taken ahead of the host (run.json "steps_ahead"), and the
    // steps computed ahead and thrown away ("steps_thrown").
    void steps_ahead(std::uint64_t taken, std::uint64_t thrown) { steps_ahead_ = taken, steps_thrown_ = thrown; }
    // Rewrites run.json with the outcome ("running", "completed", "interrupted", "failed") and the
    // last step reached; flushes the CSV streams so they are complete whatever happens next.
    // `exit_status` and `signal` (the signal that stopped the run, empty: none) go into run.json too.
    void finish(const std::string& status, const StepInfo& last, const std::string& message = {}, int exit_status = 0,
                const std::string& signal = {});
    // The run.json a second Ctrl-C or SIGTERM writes from its signal handler (status "aborted",
    // the last step known now).
    std::string abort_text(const StepInfo& last) const;
    std::string json_path() const { return dir_ + "/run.json"; }

    // A file-name-safe form of a probe or scene name ("p wall/1" -> "p_wall_1").
    static std::string safe_name(const std::string& name);

private:
    struct Ending {
        std::string status = {};
        const StepInfo* last = nullptr;
        std::string message = {};
        int exit_status = -1;  // -1: not known (still running)
        std::string signal = {};
    };
    std::string json_text(const Ending& e) const;
    void write_json(const Ending& e) const;

    std::string dir_;
    RunIdentity identity_;
    std::string started_;  // ISO 8601 UTC
    std::ofstream stats_;
    std::chrono::steady_clock::time_point last_flush_;
    std::vector<std::pair<std::string, std::unique_ptr<std::ofstream>>> probe_files_;  // by probe name
    std::vector<std::unique_ptr<std::ofstream>> body_files_;  // in Simulation::bodies() order
    std::vector<BodySample> last_bodies_;
    std::size_t table_builds_ = 0;
    std::uint64_t steps_ahead_ = 0, steps_thrown_ = 0;
    bool resumed_ = false;
    double resume_time_ = 0;
    bool writes_ = true;
};

}  // namespace clsph::app
