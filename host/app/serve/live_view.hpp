// What the run thread and the live view's server threads share (clsph run --serve): the status of
// the run, the images the page wants, the probe samples, and the page's requests (pause, resume,
// one step, write now). The run thread does all the device work, between two steps
// (between_steps); the server threads only wait on it, with a time limit, so a slow or absent
// browser costs the run nothing and many browsers cost it at most the render budget.
#pragma once
#include <clsph/render.hpp>
#include <clsph/simulation.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace clsph::app::serve {

// What the run loop lends the live view between two steps.
struct RunHooks {
    // Writes a frame and a checkpoint now (the run's own writers); returns what it wrote.
    std::function<std::string()> write_now;
    // Ctrl-C or SIGTERM: a pause gives way to it.
    std::function<bool()> stop_requested;
};

class LiveView {
public:
    // `until`: the run's end (s; infinite with --steps alone), `steps`: its step limit, if any.
    LiveView(std::size_t particles, double until, std::optional<std::uint64_t> steps);

    // --- the run thread ---
    // The run's first step (and its time) the steps/s and the ETA count from.
    void started(const StepInfo& at);
    // Between two steps: publishes the status, renders the image asked for (at most 30 a second,
    // and at most a third of the run's time), does what the page asked, and waits here while the
    // run is paused (rendering still).
    void between_steps(Simulation& sim, const RunHooks& hooks);
    void probes(const std::vector<ProbeSample>& samples);
    // The run has ended (`outcome`: completed, interrupted, failed): images are refused from now on.
    void finished(const std::string& outcome);

    // --- server threads ---
    // An image seen by `camera`, rendered by the run thread; none when the run has ended, the
    // image did not come within `wait`, or too many different views wait already (`why` says which).
    std::shared_ptr<const Image> frame(const CameraView& camera, const ImageStyle& style, std::chrono::milliseconds wait,
                                       std::string& why);
    void pause();
    void resume();
    void step_once();  // while paused: one step, then paused again
    void write_now();
    nlohmann::json status() const;
    // The probe samples after simulated time `after` (s): names, and [time, value...] rows.
    nlohmann::json probes_after(double after) const;

private:
    using clock = std::chrono::steady_clock;
    struct Wanted {
        std::uint64_t ticket;
        CameraView camera;
        ImageStyle style;
    };
    struct Done {
        std::shared_ptr<const Image> image;  // null: rendering failed
        clock::time_point at;
    };

    void publish(Simulation& sim, const StepInfo& s, bool force);
    void render_wanted(Simulation& sim, std::unique_lock<std::mutex>& lock);
    void do_requests(const RunHooks& hooks, std::unique_lock<std::mutex>& lock);

    mutable std::mutex mutex_;
    std::condition_variable run_wakes_;    // the run thread, while paused
    std::condition_variable frame_ready_;  // server threads waiting for an image

    // The status (under mutex_).
    std::string state_ = "setting up";
    std::size_t particles_;
    double until_;
    std::optional<std::uint64_t> step_limit_;
    std::uint64_t first_step_ = 0, step_ = 0;
    double first_time_ = 0, time_ = 0, steps_per_second_ = 0, sim_seconds_per_second_ = 0;
    clock::time_point first_wall_ = clock::now(), last_publish_ = clock::time_point{}, last_shares_ = clock::time_point{};
    std::uint64_t window_step_ = 0;
    double window_time_ = 0;
    clock::time_point window_wall_ = clock::now();
    nlohmann::json shares_ = nlohmann::json::array();
    std::string written_;  // what the last "write now" wrote
    std::string error_;    // the last rendering error

    // The page's requests.
    bool paused_ = false;
    std::uint64_t steps_granted_ = 0;
    bool write_wanted_ = false;

    // Images: asked for, rendered (by ticket), and the render budget.
    std::deque<Wanted> wanted_;
    std::map<std::uint64_t, Done> done_;
    std::uint64_t next_ticket_ = 1;
    clock::time_point next_render_ = clock::time_point{};
    std::uint64_t frames_rendered_ = 0;

    // Probes: names, and rows [time, values...], thinned to at most max_probe_rows.
    std::vector<std::string> probe_names_;
    std::vector<std::vector<double>> probe_rows_;
};

}  // namespace clsph::app::serve
