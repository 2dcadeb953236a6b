// What `clsph run` was asked to do, as parsed from the command line (main.cpp).
#pragma once
#include <clsph/ranks.hpp>

#include <memory>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clsph::app {
namespace serve {
class LiveView;  // serve/live_view.hpp
}

struct RunArgs {
    std::string scene_path;
    // Started by mpirun (main.cpp): this rank's place in the run (clsph/ranks.hpp); null: one process.
    std::shared_ptr<Ranks> ranks;
    std::string devices;                      // empty: $CLSPH_DEVICES or the default selection
    std::optional<double> until;              // simulated seconds; default: the scene's run.end_time
    std::optional<std::uint64_t> steps;       // stop after this many steps
    std::optional<std::string> out;           // default: out/<scene file stem>
    std::optional<double> every;              // seconds between frames; default: run.output_every
    std::vector<std::string> overrides;       // --set KEY=VALUE, in order
    std::string balance = "dynamic";          // several devices: dynamic | static | off
    std::string balance_log;                  // several devices: the balancer's per-step CSV
    bool csv = false;
    std::size_t output_stride = 1;            // --output-stride K: frames hold every K-th particle by id
    std::vector<double> output_box;           // --output-box: frames hold the particles inside (6 numbers)
    std::string fields = "all";               // --fields: the point-data arrays frames hold
    bool compress = false;                    // --compress: zlib-compressed VTU frames
    bool pieces = false;                      // --pieces: a frame is one VTU per device and a .pvtu index
    bool profile = false;
    bool synchronous = false;                 // --synchronous: Options::synchronous
    bool dry_run = false;
    bool force = false;
    std::string interaction;                  // --interaction NAME; empty: the scene's run.interaction
    std::string cell_order;                   // --cell-order NAME; empty: the scene's run.cell_order
    bool surface = false;                     // --surface: the free surface at frames (surface_*.vtp)
    std::optional<double> surface_every;      // --surface-every DT (implies --surface); default: every frame
    bool surface_ply = false;                 // --surface-ply: also .ply
    double surface_spacing = 0.0;             // --surface-spacing M; 0: dp / 2
    std::optional<double> checkpoint_every;   // --checkpoint-every DT: checkpoint_NNNNN.clsph at the first frame past each DT
    std::size_t checkpoint_keep = 3;          // --checkpoint-keep K: the last K checkpoints kept
    bool no_checkpoint = false;               // --no-checkpoint: none at all, not even at the end
    // --on-device-failure: stop (exit 3) or continue (back to the last checkpoint, the remaining devices).
    std::string on_device_failure = "stop";
    bool render = false;                      // --render: an image per surface (implies --surface)
    bool video = false;                       // --video: an MP4 of the images (implies --render)
    std::string render_method;                // --render-method surface|splat; empty: the scene's render.method
    std::optional<int> serve;                 // --serve [PORT]: the live view (docs/live_view.md) on this port
    std::string serve_host = "127.0.0.1";     // --serve-host ADDR: where it listens (default: this machine only)
    // With --serve, set by run_command once the server listens: what the run loop shows it.
    std::shared_ptr<serve::LiveView> live;
    std::vector<std::string> command_line;    // argv, for run.json
    // clsph resume: the output directory to go on in (frames, stats and probes continue there).
    std::string resume_dir;
    std::vector<std::string> resume_command_line;  // the resume's own argv (run.json "resumes")
    std::string resume_reason;                     // why (run.json "resumes"): empty for clsph resume
    // The test build's seams (test_seams.hpp; clsph-faulty, never the shipped clsph) apply to this
    // run. Off after a failover, whose failure was the injected fault: the devices left run clean.
    bool test_seams = true;

    // Any of --surface, --surface-every, --surface-ply, --surface-spacing, --render, --video.
    bool wants_surface() const {
        return surface || surface_every || surface_ply || surface_spacing > 0 || render || video;
    }
    // Surface meshes asked for themselves (not only for images): any but --render and --video.
    bool wants_meshes() const { return surface || surface_every || surface_ply || surface_spacing > 0; }
};

// The most steps --steps takes (a run of 10^12 steps is years on any machine; more is a typo).
constexpr std::uint64_t max_steps = 1000000000000ULL;

// Exit codes of `clsph run` (also in the README).
enum ExitCode : int {
    exit_ok = 0,
    exit_error = 1,             // bad scene, device, output directory, I/O
    exit_simulation_failed = 2, // the physics blew up; the last good state was written
    exit_device_failed = 3,     // a device failed (mid-run: the last good state was written)
    exit_interrupted = 130,     // Ctrl-C: stopped cleanly after a final frame (128 + SIGINT)
    exit_terminated = 143,      // SIGTERM: the same as Ctrl-C (128 + SIGTERM)
};

}  // namespace clsph::app
