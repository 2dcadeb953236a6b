#include "multi/force_timer.hpp"

#include "cl/errors.hpp"
#include "clsph/error.hpp"

#include <atomic>
#include <chrono>
#include <thread>

namespace clsph::multi {

struct ForceTimer::Stamp {
    std::atomic<bool> done{false};
    std::atomic<long long> ns{0};
};

namespace {
using Clock = std::chrono::steady_clock;

void CL_CALLBACK on_complete(cl_event, cl_int, void* data) {
    auto* stamp = static_cast<std::shared_ptr<ForceTimer::Stamp>*>(data);
    (*stamp)->ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
    (*stamp)->done = true;
    delete stamp;
}

cl::Event marker(cl_rt::Device& d, std::shared_ptr<ForceTimer::Stamp>* stamp) {
    cl::Event ev;
    cl_rt::check(d.queue().enqueueMarkerWithWaitList(nullptr, &ev), "enqueueing the force timer's marker", d.label());
    if (stamp) {
        *stamp = std::make_shared<ForceTimer::Stamp>();
        auto* held = new std::shared_ptr<ForceTimer::Stamp>(*stamp);
        const cl_int err = ev.setCallback(CL_COMPLETE, on_complete, held);
        if (err != CL_SUCCESS) delete held;
        cl_rt::check(err, "setting the force timer's callback", d.label());
    }
    return ev;
}
}  // namespace

ForceTimer::ForceTimer(cl_rt::Device& device) : device_(device), host_clocks_(device.quirks().fake_event_timestamps) {}

void ForceTimer::begin(bool more) {
    if (!more) parts_.clear();
    Part part;
    if (host_clocks_) {
        // rusticl completes a flushed batch's events together, so a marker's callback before the
        // pass fires when the pass has ended (a pass of 290 ms timed as 18 us, which put a whole
        // dam break on llvmpipe). So: wait for what is queued, read the clock, then enqueue the pass.
        device_.finish();
        part.begin_stamp = std::make_shared<Stamp>();
        part.begin_stamp->ns =
            std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
        part.begin_stamp->done = true;
    }
    part.begin = marker(device_, nullptr);
    parts_.push_back(std::move(part));
}

void ForceTimer::end() {
    if (parts_.empty() || parts_.back().end()) throw Error("the force timer's end() without its begin()");
    Part& part = parts_.back();
    part.end = marker(device_, host_clocks_ ? &part.end_stamp : nullptr);
}

double ForceTimer::seconds() {
    double sum = 0.0;
    for (Part& part : parts_) {
        if (!part.begin() || !part.end()) continue;
        if (host_clocks_) {
            // Callbacks may run a little after the event wait returns: give them up to a second.
            const auto give_up = Clock::now() + std::chrono::seconds(1);
            while (!(part.begin_stamp->done && part.end_stamp->done) && Clock::now() < give_up)
                std::this_thread::sleep_for(std::chrono::microseconds(20));
            if (part.begin_stamp->done && part.end_stamp->done)
                sum += 1e-9 * static_cast<double>(part.end_stamp->ns - part.begin_stamp->ns);
        } else {
            cl_rt::check(part.end.wait(), "waiting for the force timer's marker", device_.label());
            const auto t0 = part.begin.getProfilingInfo<CL_PROFILING_COMMAND_END>();
            const auto t1 = part.end.getProfilingInfo<CL_PROFILING_COMMAND_END>();
            sum += t1 > t0 ? 1e-9 * static_cast<double>(t1 - t0) : 0.0;
        }
    }
    parts_.clear();
    return sum;
}

}  // namespace clsph::multi
