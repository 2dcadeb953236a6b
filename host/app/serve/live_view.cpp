#include "live_view.hpp"

#include <clsph/error.hpp>
#include <clsph/interaction.hpp>

#include <algorithm>
#include <cmath>

namespace clsph::app::serve {
namespace {

constexpr std::size_t max_views_waiting = 64;  // distinct cameras queued at once; more: 503
constexpr std::size_t max_probe_rows = 4000;   // then every other row goes
constexpr auto frame_interval = std::chrono::microseconds(1000000 / 30);  // 30 images a second at most
// Rendering takes at most 1 / (1 + render_spacing) of the run thread's time: after an image that
// took r seconds, the next waits max(1/30 s, render_spacing * r).
constexpr double render_spacing = 2.0;

bool same_view(const CameraView& a, const ImageStyle& sa, const CameraView& b, const ImageStyle& sb) {
    auto same = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
    return sa.surface == sb.surface && same(sa.range_min, sb.range_min) && same(sa.range_max, sb.range_max) && a.eye == b.eye && a.target == b.target && a.up == b.up && a.fov_deg == b.fov_deg &&
           a.width == b.width && a.height == b.height;
}

}  // namespace

LiveView::LiveView(std::size_t particles, double until, std::optional<std::uint64_t> steps)
    : particles_(particles), until_(until), step_limit_(steps) {}

void LiveView::started(const StepInfo& at) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = paused_ ? "paused" : "running";
    first_step_ = step_ = window_step_ = at.step;
    first_time_ = time_ = window_time_ = at.time;
    particles_ = at.particles;
    first_wall_ = window_wall_ = clock::now();
}

void LiveView::publish(Simulation& sim, const StepInfo& s, bool force) {
    const auto now = clock::now();
    // The shares ask every device: a few times a second is enough for a status bar.
    const bool shares_due = force || now - last_shares_ > std::chrono::milliseconds(250);
    nlohmann::json shares = nlohmann::json::array();
    if (shares_due) {
        for (const auto& d : sim.shares())
            shares.push_back({{"device", d.device},
                              {"particles", d.particles},
                              {"first_column", d.first_column},
                              {"end_column", d.end_column},
                              {"interaction", interaction_name(d.interaction)}});
    }
    std::lock_guard<std::mutex> lock(mutex_);
    step_ = s.step;
    time_ = s.time;
    particles_ = s.particles;
    if (shares_due) {
        shares_ = std::move(shares);
        last_shares_ = now;
    }
    // Rates over the last second or so (a paused stretch restarts the window).
    const double wall = std::chrono::duration<double>(now - window_wall_).count();
    if (wall >= 1.0) {
        steps_per_second_ = static_cast<double>(s.step - window_step_) / wall;
        sim_seconds_per_second_ = (s.time - window_time_) / wall;
        window_step_ = s.step;
        window_time_ = s.time;
        window_wall_ = now;
    } else if (steps_per_second_ == 0 && wall > 0.2) {
        steps_per_second_ = static_cast<double>(s.step - window_step_) / wall;
        sim_seconds_per_second_ = (s.time - window_time_) / wall;
    }
    last_publish_ = now;
}

void LiveView::between_steps(Simulation& sim, const RunHooks& hooks) {
    publish(sim, sim.info(), false);
    std::unique_lock<std::mutex> lock(mutex_);
    render_wanted(sim, lock);
    do_requests(hooks, lock);
    if (!paused_) return;
    if (steps_granted_ > 0) {
        --steps_granted_;
        return;
    }
    state_ = "paused";
    while (paused_ && steps_granted_ == 0 && !hooks.stop_requested()) {
        // Woken by a request; the time limit lets Ctrl-C in.
        run_wakes_.wait_for(lock, std::chrono::milliseconds(50));
        render_wanted(sim, lock);
        do_requests(hooks, lock);
    }
    if (steps_granted_ > 0) --steps_granted_;
    state_ = paused_ ? "paused" : "running";
    // The steps/s of the stretch after the pause, not an average over it.
    window_step_ = step_;
    window_time_ = time_;
    window_wall_ = clock::now();
}

void LiveView::render_wanted(Simulation& sim, std::unique_lock<std::mutex>& lock) {
    const auto start = clock::now();
    if (wanted_.empty() || start < next_render_) return;
    // The oldest view asked for, and every request for the same view with it.
    const CameraView camera = wanted_.front().camera;
    const ImageStyle style = wanted_.front().style;
    std::vector<std::uint64_t> tickets;
    for (auto it = wanted_.begin(); it != wanted_.end();) {
        if (same_view(it->camera, it->style, camera, style)) {
            tickets.push_back(it->ticket);
            it = wanted_.erase(it);
        } else {
            ++it;
        }
    }
    lock.unlock();
    std::shared_ptr<const Image> image;
    std::string error;
    try {
        image = std::make_shared<const Image>(sim.image(camera, style));
    } catch (const DeviceError&) {
        lock.lock();
        throw;  // a device failure is the run's, reported as any other
    } catch (const Error& e) {
        error = e.what();
    }
    const auto end = clock::now();
    lock.lock();
    if (!error.empty()) error_ = error;
    ++frames_rendered_;
    // While paused there is no run to share the thread with; the first image (which builds the
    // surface and render kernels) says nothing about the next.
    const bool first = frames_rendered_ == 1;
    const auto took = paused_ || first ? clock::duration{} : std::chrono::duration_cast<clock::duration>((end - start) * render_spacing);
    next_render_ = end + std::max<clock::duration>(frame_interval, took);
    // Results nobody came back for (their request timed out) are dropped after a while.
    for (auto it = done_.begin(); it != done_.end();) it = end - it->second.at > std::chrono::seconds(10) ? done_.erase(it) : std::next(it);
    for (auto t : tickets) done_[t] = Done{image, end};
    frame_ready_.notify_all();
}

void LiveView::do_requests(const RunHooks& hooks, std::unique_lock<std::mutex>& lock) {
    if (!write_wanted_) return;
    write_wanted_ = false;
    lock.unlock();
    std::string what;
    try {
        what = hooks.write_now();
    } catch (...) {
        lock.lock();
        throw;  // a writer error ends the run, as it would at a frame
    }
    lock.lock();
    written_ = what;
}

void LiveView::probes(const std::vector<ProbeSample>& samples) {
    if (samples.empty()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (probe_names_.empty())
        for (const auto& s : samples) probe_names_.push_back(s.name);
    std::vector<double> row{samples.front().time};
    for (const auto& s : samples) row.push_back(s.value);
    if (!probe_rows_.empty() && probe_rows_.back().front() >= row.front()) return;  // a resampled time
    probe_rows_.push_back(std::move(row));
    if (probe_rows_.size() > max_probe_rows) {
        std::vector<std::vector<double>> kept;
        for (std::size_t i = 0; i < probe_rows_.size(); i += 2) kept.push_back(std::move(probe_rows_[i]));
        probe_rows_ = std::move(kept);
    }
}

void LiveView::finished(const std::string& outcome) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = outcome;
    paused_ = false;
    wanted_.clear();
    frame_ready_.notify_all();
}

std::shared_ptr<const Image> LiveView::frame(const CameraView& camera, const ImageStyle& style, std::chrono::milliseconds wait,
                                             std::string& why) {
    std::unique_lock<std::mutex> lock(mutex_);
    auto ended = [&] { return state_ != "setting up" && state_ != "running" && state_ != "paused"; };
    if (ended()) {
        why = "the run has ended (" + state_ + ")";
        return nullptr;
    }
    if (wanted_.size() >= max_views_waiting) {
        why = "too many views wait for an image; try again";
        return nullptr;
    }
    const std::uint64_t ticket = next_ticket_++;
    wanted_.push_back(Wanted{ticket, camera, style});
    run_wakes_.notify_one();
    const bool ready = frame_ready_.wait_for(lock, wait, [&] { return done_.count(ticket) > 0 || ended(); });
    if (!ready || !done_.count(ticket)) {
        wanted_.erase(std::remove_if(wanted_.begin(), wanted_.end(), [&](const Wanted& w) { return w.ticket == ticket; }),
                      wanted_.end());
        why = ended() ? "the run has ended (" + state_ + ")"
                      : state_ == "setting up" ? "the run is still setting up" : "no image within the time limit";
        return nullptr;
    }
    auto image = done_[ticket].image;
    done_.erase(ticket);
    if (!image) why = "rendering failed: " + error_;
    return image;
}

void LiveView::pause() {
    std::lock_guard<std::mutex> lock(mutex_);
    paused_ = true;
    steps_granted_ = 0;
}

void LiveView::resume() {
    std::lock_guard<std::mutex> lock(mutex_);
    paused_ = false;
    run_wakes_.notify_one();
}

void LiveView::step_once() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!paused_) return;  // running: every step is taken anyway
    ++steps_granted_;
    run_wakes_.notify_one();
}

void LiveView::write_now() {
    std::lock_guard<std::mutex> lock(mutex_);
    write_wanted_ = true;
    run_wakes_.notify_one();
}

nlohmann::json LiveView::status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    nlohmann::json j = {{"state", state_},
                        {"paused", paused_},
                        {"step", step_},
                        {"time", time_},
                        {"particles", particles_},
                        {"steps_per_second", steps_per_second_},
                        {"devices", shares_},
                        {"frames_rendered", frames_rendered_},
                        {"written", written_},
                        {"render_error", error_}};
    j["until"] = std::isfinite(until_) ? nlohmann::json(until_) : nlohmann::json(nullptr);
    j["step_limit"] = step_limit_ ? nlohmann::json(*step_limit_) : nlohmann::json(nullptr);
    // ETA: by simulated time when the run ends at a time, else by steps; null while unknown.
    nlohmann::json eta = nullptr;
    if (state_ == "running") {
        double left = INFINITY;
        if (std::isfinite(until_) && sim_seconds_per_second_ > 0) left = (until_ - time_) / sim_seconds_per_second_;
        if (step_limit_ && steps_per_second_ > 0) {
            const double steps_left = static_cast<double>(first_step_ + *step_limit_) - static_cast<double>(step_);
            left = std::min(left, steps_left / steps_per_second_);
        }
        if (std::isfinite(left)) eta = std::max(0.0, left);
    }
    j["eta_seconds"] = eta;
    j["wall_seconds"] = std::chrono::duration<double>(clock::now() - first_wall_).count();
    return j;
}

nlohmann::json LiveView::probes_after(double after) const {
    std::lock_guard<std::mutex> lock(mutex_);
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& r : probe_rows_)
        if (r.front() > after) rows.push_back(r);
    return {{"names", probe_names_}, {"rows", rows}};
}

}  // namespace clsph::app::serve
