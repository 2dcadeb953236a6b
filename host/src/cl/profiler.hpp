// Per-launch names and times. With profiling on, each launch's time comes from its event, or from
// host clocks around a finish() where the driver's timestamps are not trustworthy (quirks).
#pragma once
#include "cl/cl.hpp"

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace clsph::cl_rt {

// One profiled command's device timestamps (ns, the device's own clock): a timeline.
struct TraceSpan {
    std::string name;
    std::uint64_t start = 0, end = 0;
};

struct KernelStats {
    std::size_t calls = 0;
    double seconds = 0.0;
};

class Profiler {
public:
    explicit Profiler(bool host_timed) : host_timed_(host_timed) {}
    bool enabled() const { return enabled_; }
    void enable(bool on) { enabled_ = on; }
    bool host_timed() const { return host_timed_; }

    void add_event(const std::string& name, cl::Event event) { pending_.push_back({name, std::move(event)}); }
    void add_seconds(const std::string& name, double s) {
        auto& k = stats_[name];
        k.calls += 1;
        k.seconds += s;
    }
    // Waits for pending events and folds their times into the totals.
    void collect();
    // Folds in the pending events that have completed, up to the first that has not, without
    // waiting: the host can do this while a long kernel runs, so a later collect() is short.
    void collect_finished();
    const std::map<std::string, KernelStats>& stats() { collect(); return stats_; }
    void clear() { pending_.clear(); stats_.clear(); }
    // With tracing on, collect() also keeps every command's start and end (see take_trace()).
    void trace(bool on) { tracing_ = on; }
    std::vector<TraceSpan> take_trace() { collect(); return std::move(trace_); }

private:
    struct Pending { std::string name; cl::Event event; };
    void fold(Pending& p);
    bool host_timed_;
    bool enabled_ = false;
    std::vector<Pending> pending_;
    std::map<std::string, KernelStats> stats_;
    bool tracing_ = false;
    std::vector<TraceSpan> trace_;
};

}  // namespace clsph::cl_rt
