#include "progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace clsph::app {
namespace {

constexpr double terminal_interval = 0.25;  // s between redraws of the terminal line
constexpr double log_interval = 10.0;       // s between log lines when not on a terminal

}  // namespace

std::string format_duration(double seconds) {
    char text[32];
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const long s = std::lround(seconds);
    if (seconds < 60)
        std::snprintf(text, sizeof text, "%.1fs", seconds);
    else if (s < 3600)
        std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
    return text;
}

std::string format_shares(const std::vector<DeviceShare>& shares) {
    if (shares.size() < 2) return {};
    std::size_t total = 0;
    for (const auto& d : shares) total += d.particles;
    std::string out;
    for (const auto& d : shares) {
        const double pct = total ? 100.0 * static_cast<double>(d.particles) / static_cast<double>(total) : 0.0;
        out += (out.empty() ? "" : "/") + std::to_string(static_cast<long>(std::lround(pct)));
    }
    return out + " %";
}

Progress::Progress(double t_start, double t_end, std::optional<std::uint64_t> max_steps, bool terminal)
    : t_start_(t_start),
      t_end_(t_end),
      max_steps_(max_steps),
      terminal_(terminal),
      start_(clock::now()),  // made just before the first step: ETA counts stepping, not set-up
      last_print_(start_) {}

double Progress::fraction(const StepInfo& s) const {
    double f = 0.0;
    if (std::isfinite(t_end_) && t_end_ > t_start_) f = (s.time - t_start_) / (t_end_ - t_start_);
    if (max_steps_ && *max_steps_ > 0)
        f = std::max(f, static_cast<double>(s.step - first_step_) / static_cast<double>(*max_steps_));
    return std::clamp(f, 0.0, 1.0);
}

std::string Progress::line(const StepInfo& s, const Simulation& sim, double seconds_since_last) const {
    const double f = fraction(s);
    const double elapsed = std::chrono::duration<double>(clock::now() - start_).count();
    const double rate = seconds_since_last > 0 ? static_cast<double>(s.step - last_step_) / seconds_since_last : 0.0;
    const double eta = f > 0 ? elapsed * (1.0 - f) / f : -1.0;
    char text[256];
    if (std::isfinite(t_end_))
        std::snprintf(text, sizeof text, "t %.4f / %.4f s (%3.0f%%)", s.time, t_end_, 100.0 * f);
    else
        std::snprintf(text, sizeof text, "t %.4f s (%3.0f%%)", s.time, 100.0 * f);
    std::string out = text;
    std::snprintf(text, sizeof text, " | step %llu | %.1f steps/s | ETA %s | %zu particles, %zu removed",
                  static_cast<unsigned long long>(s.step), rate, format_duration(eta).c_str(), s.particles,
                  s.removed);
    out += text;
    const std::string split = format_shares(sim.shares());
    if (!split.empty()) out += " | split " + split;
    return out;
}

void Progress::update(const StepInfo& s, const Simulation& sim) {
    const auto now = clock::now();
    if (!started_) {  // the step count of a resumed simulation need not start at 0
        started_ = true;
        first_step_ = last_step_ = s.step - 1;
    }
    const double since = std::chrono::duration<double>(now - last_print_).count();
    if (terminal_) {
        if (since < terminal_interval) return;
        std::cerr << "\r\033[K" << line(s, sim, since) << std::flush;
        line_shown_ = true;
    } else {
        const int decile = static_cast<int>(10.0 * fraction(s));
        if (since < log_interval && decile <= last_decile_) return;
        last_decile_ = decile;
        std::cout << line(s, sim, since) << std::endl;
    }
    last_print_ = now;
    last_step_ = s.step;
}

void Progress::clear() {
    if (terminal_ && line_shown_) std::cerr << "\r\033[K" << std::flush;
    line_shown_ = false;
}

}  // namespace clsph::app
