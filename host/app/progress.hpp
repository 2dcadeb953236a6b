// Progress of a run: on a terminal a line on stderr redrawn a few times a second; otherwise (a log
// file, CI) a plain line on stdout every ~10 s of wall time or every 10 % of the run, so logs show
// the run advancing without drowning in carriage returns.
#pragma once
#include <clsph/simulation.hpp>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clsph::app {

class Progress {
public:
    // The run goes from simulated time `t_start` to `t_end` (may be infinite when only a step
    // count bounds it) or until `max_steps` steps, whichever comes first.
    Progress(double t_start, double t_end, std::optional<std::uint64_t> max_steps, bool terminal);

    // `sim` gives each device's share of the particles, shown when there are several devices.
    void update(const StepInfo& s, const Simulation& sim);
    // Erases the terminal line, so that what is printed next starts on a clean line.
    void clear();

private:
    using clock = std::chrono::steady_clock;
    double fraction(const StepInfo& s) const;
    std::string line(const StepInfo& s, const Simulation& sim, double seconds_since_last) const;

    double t_start_, t_end_;
    std::optional<std::uint64_t> max_steps_;
    bool terminal_;
    clock::time_point start_, last_print_;
    std::uint64_t first_step_ = 0;
    bool started_ = false;
    std::uint64_t last_step_ = 0;
    int last_decile_ = 0;
    bool line_shown_ = false;
};

// "1h02m", "3m07s", "12.3s"
std::string format_duration(double seconds);

// Each device's share of the particles, "52/31/17 %"; empty for a single device.
std::string format_shares(const std::vector<DeviceShare>& shares);

}  // namespace clsph::app
