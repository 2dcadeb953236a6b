#include "cl/async.hpp"

#include "cl/device.hpp"
#include "cl/errors.hpp"

#include <algorithm>
#include <chrono>
#include <thread>
#include <condition_variable>
#include <memory>
#include <mutex>

namespace clsph::cl_rt {
namespace {
struct WaitState {
    std::mutex m;
    std::condition_variable cv;
    std::size_t left = 0;
    cl_int worst = CL_SUCCESS;
    std::size_t failed = 0;  // index of the first event that failed
};

struct CallbackArg {
    std::shared_ptr<WaitState> state;
    std::size_t index;
};

void CL_CALLBACK on_complete(cl_event, cl_int status, void* user) {
    std::unique_ptr<CallbackArg> arg(static_cast<CallbackArg*>(user));
    WaitState& s = *arg->state;
    std::lock_guard<std::mutex> lock(s.m);
    if (status < 0 && s.worst == CL_SUCCESS) {
        s.worst = status;
        s.failed = arg->index;
    }
    if (--s.left == 0) s.cv.notify_all();
}
}  // namespace

void EventSet::add(Device& device, cl::Event event) {
    std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back(std::move(event));
    devices_.push_back(&device);
}

std::vector<cl::Event> EventSet::events_of(const Device& device) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<cl::Event> out;
    for (std::size_t i = 0; i < events_.size(); ++i)
        if (devices_[i] == &device) out.push_back(events_[i]);
    return out;
}

void EventSet::wait(const std::string& what, Mode mode) {
    if (events_.empty()) return;
    // Whatever happens below, the set is empty afterwards.
    std::vector<cl::Event> events;
    std::vector<Device*> devices;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        events.swap(events_);
        devices.swap(devices_);
    }
    // Every queue involved is submitted once, so no event waits on a command still on the host.
    std::vector<Device*> flushed;
    for (Device* d : devices) {
        if (std::find(flushed.begin(), flushed.end(), d) != flushed.end()) continue;
        check(d->queue().flush(), what + " (flushing the queue)", d->label());
        check(d->transfer_queue().flush(), what + " (flushing the transfer queue)", d->label());
        flushed.push_back(d);
        if (mode == Mode::callbacks && d->quirks().late_transfer_callbacks) mode = Mode::poll;
    }
    if (mode == Mode::block) {
        for (std::size_t i = 0; i < events.size(); ++i) check(clWaitForEvents(1, &events[i]()), what, devices[i]->label());
        return;
    }
    if (mode == Mode::poll) {
        // Events complete roughly in order: look at the first pending one, sleep between looks.
        for (std::size_t next = 0; next < events.size();) {
            cl_int status = CL_QUEUED;
            check(clGetEventInfo(events[next](), CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr), what,
                  devices[next]->label());
            check(status < 0 ? status : CL_SUCCESS, what, devices[next]->label());
            if (status == CL_COMPLETE)
                ++next;
            else
                std::this_thread::sleep_for(std::chrono::microseconds(20));
        }
        return;
    }
    auto state = std::make_shared<WaitState>();
    state->left = events.size();
    for (std::size_t i = 0; i < events.size(); ++i) {
        auto* arg = new CallbackArg{state, i};
        const cl_int err = clSetEventCallback(events[i](), CL_COMPLETE, &on_complete, arg);
        if (err != CL_SUCCESS) {
            // No callback: wait for this one the plain way.
            delete arg;
            const cl_int w = clWaitForEvents(1, &events[i]());
            std::lock_guard<std::mutex> lock(state->m);
            if (w != CL_SUCCESS && state->worst == CL_SUCCESS) {
                state->worst = w;
                state->failed = i;
            }
            --state->left;
        }
    }
    std::unique_lock<std::mutex> lock(state->m);
    state->cv.wait(lock, [&] { return state->left == 0; });
    const cl_int worst = state->worst;
    Device* failed = devices[state->failed];
    lock.unlock();
    check(worst, what, failed->label());
}

PinnedHost::~PinnedHost() { release(); }

void PinnedHost::release() {
    if (data_ && device_) {
        // Unmapping is enqueued; finishing here keeps the memory valid until the driver is done.
        // A failure here (a lost device) leaves nothing to recover: the buffer goes anyway.
        try {
            device_->queue().enqueueUnmapMemObject(buffer_, data_);
            device_->queue().finish();
        } catch (const cl::Error&) {
        }
    }
    data_ = nullptr;
    bytes_ = 0;
    buffer_ = cl::Buffer();
}

bool PinnedHost::reserve(Device& device, std::size_t bytes, double headroom) {
    if (bytes <= bytes_ && device_ == &device) return false;
    release();
    device_ = &device;
    const std::size_t want = static_cast<std::size_t>(static_cast<double>(std::max<std::size_t>(bytes, 1)) * (1.0 + headroom));
    guarded("allocating " + std::to_string(want) + " bytes of pinned host memory", device.label(), [&] {
        device.faults().before(testing::FaultCall::allocation, "clCreateBuffer");
        buffer_ = cl::Buffer(device.context(), CL_MEM_ALLOC_HOST_PTR | CL_MEM_READ_WRITE, want);
        data_ = static_cast<unsigned char*>(
            device.queue().enqueueMapBuffer(buffer_, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, want));
    });
    bytes_ = want;
    return true;
}

}  // namespace clsph::cl_rt
