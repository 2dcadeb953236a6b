#include "multi/force_timer.hpp"

#include "cl/errors.hpp"

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

void ForceTimer::begin() {
    if (host_clocks_) {
        // rusticl completes a flushed batch's events together, so a marker's callback before the
        // pass fires when the pass has ended (a pass of 290 ms timed as 18 us, which put a whole
        // dam break on llvmpipe). So: wait for what is queued, read the clock, then enqueue the pass.
        device_.finish();
        begin_stamp_ = std::make_shared<Stamp>();
        begin_stamp_->ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
        begin_stamp_->done = true;
    }
    begin_ = marker(device_, nullptr);
}

void ForceTimer::end() { end_ = marker(device_, host_clocks_ ? &end_stamp_ : nullptr); }

double ForceTimer::seconds() {
    if (!begin_() || !end_()) return 0.0;
    double s = 0.0;
    if (host_clocks_) {
        // Callbacks may run a little after the event wait returns: give them up to a second.
        const auto give_up = Clock::now() + std::chrono::seconds(1);
        while (!(begin_stamp_->done && end_stamp_->done) && Clock::now() < give_up)
            std::this_thread::sleep_for(std::chrono::microseconds(20));
        if (begin_stamp_->done && end_stamp_->done) s = 1e-9 * static_cast<double>(end_stamp_->ns - begin_stamp_->ns);
    } else {
        cl_rt::check(end_.wait(), "waiting for the force timer's marker", device_.label());
        const auto t0 = begin_.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        const auto t1 = end_.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        s = t1 > t0 ? 1e-9 * static_cast<double>(t1 - t0) : 0.0;
    }
    begin_ = cl::Event();
    end_ = cl::Event();
    return s;
}

}  // namespace clsph::multi
