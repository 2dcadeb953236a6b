#include "cl/relay.hpp"

#include "cl/device.hpp"
#include "cl/errors.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

namespace clsph::cl_rt {
Relay::~Relay() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(shared_->m);
        shared_->stop = true;
        shared_->give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    }
    shared_->cv.notify_all();
    thread_.join();
    // Copies whose source never completed (a failed device): their receivers' queues are freed
    // with an error rather than left waiting.
    for (auto& job : shared_->jobs) {
        try {
            job->done.setStatus(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST);
        } catch (const cl::Error&) {
        }
    }
}

bool Relay::same_context(Device& a, Device& b) { return a.context()() == b.context()(); }

void Relay::start() {
    if (thread_.joinable()) return;
    shared_ = std::make_shared<Shared>();
    thread_ = std::thread([this] { run(); });
}

namespace {
struct CallbackArg {
    std::shared_ptr<void> shared;  // keeps the relay's queue alive for a callback that comes late
    std::function<void(cl_int)> signal;
};
void CL_CALLBACK signal_done(cl_event, cl_int status, void* user) {
    std::unique_ptr<CallbackArg> arg(static_cast<CallbackArg*>(user));
    arg->signal(status);
}
}  // namespace

void Relay::copy(Device& from, Device& to, const std::vector<Piece>& pieces, PinnedHost& staging) {
    std::size_t total = 0;
    for (const auto& p : pieces) total += p.bytes;
    if (total == 0) return;
    if (same_context(from, to)) {
        // One context: the receiver's queue waits for the sender's marker, then copies on the device.
        cl::Event marker;
        check(from.queue().enqueueMarkerWithWaitList(nullptr, &marker), "marking a copy's source", from.label());
        check(from.queue().flush(), "submitting a copy's source", from.label());
        const std::vector<cl::Event> after{marker};
        for (const auto& p : pieces) {
            if (p.bytes == 0) continue;
            check(to.queue().enqueueCopyBuffer(p.src->get(), p.dst->get(), p.src_offset, p.dst_offset, p.bytes, &after),
                  "copying from " + from.label(), to.label());
        }
        return;
    }
    start();
    // Made beforehand, with nothing in flight: mapping it here would wait for `from`'s queue.
    if (staging.bytes() < total) throw Error("internal: a copy between devices without its staging (" + from.label() + ")");
    EventSet read;
    unsigned char* at = staging.data();
    for (const auto& p : pieces) {
        from.read_async(*p.src, at, p.bytes, p.src_offset, read);
        at += p.bytes;
    }
    auto events = read.events_of(from);
    auto job = std::make_shared<Job>();
    job->ready = events.back();  // an in-order queue: the last read completes after the others
    job->done = cl::UserEvent(to.context());
    job->to = &to;
    job->from = &from;
    job->pieces = pieces;
    job->staged = staging.data();
    // The write goes after what the receiver's compute queue holds now (it may still read the
    // ghosts the write replaces), and the queue goes no further until the write has landed.
    check(to.queue().enqueueMarkerWithWaitList(nullptr, &job->after), "marking a copy's place", to.label());
    const std::vector<cl::Event> wait{job->done};
    check(to.queue().enqueueBarrierWithWaitList(&wait, nullptr), "waiting for a copy from " + from.label(), to.label());
    {
        std::lock_guard<std::mutex> lock(shared_->m);
        shared_->jobs.push_back(job);
    }
    watch(job->ready, job, &Job::status, &Job::polled, from.quirks().late_transfer_callbacks);
    check(from.queue().flush(), "submitting a copy's source", from.label());
}

void Relay::watch(const cl::Event& event, const std::shared_ptr<Job>& job, cl_int Job::*status, bool Job::*polled,
                  bool late) {
    // The event's completion sets job->*status and wakes the relay's thread; where callbacks come
    // late (cl/quirks.hpp) or cannot be set, the thread looks at the event's status instead.
    if (!late) {
        auto shared = shared_;
        auto* arg = new CallbackArg{shared, [shared, job, status](cl_int st) {
                                        {
                                            std::lock_guard<std::mutex> lock(shared->m);
                                            (*job).*status = st < 0 ? st : CL_COMPLETE;
                                        }
                                        shared->cv.notify_all();
                                    }};
        cl_int err = CL_SUCCESS;
        try {
            err = cl::Event(event).setCallback(CL_COMPLETE, &signal_done, arg);
        } catch (const cl::Error& e) {
            err = e.err();
        }
        if (err == CL_SUCCESS) return;
        delete arg;
    }
    {
        std::lock_guard<std::mutex> lock(shared_->m);
        (*job).*polled = true;
    }
    shared_->cv.notify_all();
}

cl::CommandQueue& Relay::queue_for(Device* from, Device& to) {
    // Its own queue for each sender and receiver: not the receiver's transfer queue, which already
    // holds the reads of later steps' records, waiting for this copy; nor one queue per receiver,
    // where a copy from one neighbour would wait behind one from the other that waits for it.
    auto it = queues_.find({from, &to});
    if (it == queues_.end()) {
        cl_int err = CL_SUCCESS;
        cl::CommandQueue q(to.context(), to.cl_device(), 0, &err);
        check(err, "creating a queue for copies from other devices", to.label());
        it = queues_.emplace(std::make_pair(from, &to), std::move(q)).first;
    }
    return it->second;
}

namespace {
// The status of an event looked at now: CL_COMPLETE, an error (< 0), or CL_QUEUED while it runs.
cl_int look(const cl::Event& e) {
    cl_int st = CL_QUEUED;
    if (clGetEventInfo(e(), CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof st, &st, nullptr) != CL_SUCCESS) return -1;
    return st < 0 ? st : st == CL_COMPLETE ? CL_COMPLETE : CL_QUEUED;
}
}  // namespace

void Relay::run() {
    // Each job in two stages, never waiting for one: its read done -> its write enqueued; its
    // write done -> the receiver's user event set. A job waits on its own events only, so copies
    // into one device from two neighbours finish in whatever order their devices allow.
    std::unique_lock<std::mutex> lock(shared_->m);
    for (;;) {
        bool polling = false;
        std::shared_ptr<Job> job;
        for (auto& j : shared_->jobs) {
            if (j->polled && j->status == CL_QUEUED) j->status = look(j->ready);
            if (j->write_polled && j->written_status == CL_QUEUED) j->written_status = look(j->written);
            const bool waiting = j->writing ? j->written_status == CL_QUEUED : j->status == CL_QUEUED;
            if (!waiting) {
                job = j;
                break;
            }
            polling = polling || (j->writing ? j->write_polled : j->polled);
        }
        if (!job) {
            // Stopping: once nothing is left, or nothing has moved for two seconds (a failed
            // device's reads that never end; the destructor fails what is left).
            if (shared_->stop && (shared_->jobs.empty() || std::chrono::steady_clock::now() > shared_->give_up)) return;
            if (shared_->stop) polling = true;
            if (polling)
                shared_->cv.wait_for(lock, std::chrono::microseconds(20));
            else
                shared_->cv.wait(lock);
            continue;
        }
        cl_int status = job->writing ? job->written_status : job->status;
        if (!job->writing && status == CL_COMPLETE) {
            // The data is in host memory: its write, after the receiver's marker.
            job->writing = true;
            lock.unlock();
            try {
                const unsigned char* at = job->staged;
                const std::vector<cl::Event> after{job->after};
                Device& to = *job->to;
                cl::CommandQueue& queue = queue_for(job->from, to);
                for (const auto& p : job->pieces) {
                    check(queue.enqueueWriteBuffer(p.dst->get(), CL_FALSE, p.dst_offset, p.bytes, at, &after, &job->written),
                          "writing a copy from another device", to.label());
                    at += p.bytes;
                }
                check(queue.flush(), "submitting a copy from another device", to.label());
                watch(job->written, job, &Job::written_status, &Job::write_polled, to.quirks().late_transfer_callbacks);
            } catch (const std::exception&) {
                std::lock_guard<std::mutex> l(shared_->m);
                job->written_status = CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST;
            }
            lock.lock();
            continue;
        }
        // Written (or failed): the receiver's queue goes on (or fails from here).
        shared_->jobs.erase(std::find(shared_->jobs.begin(), shared_->jobs.end(), job));
        shared_->give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        lock.unlock();
        try {
            job->done.setStatus(status == CL_COMPLETE ? CL_COMPLETE : status < 0 ? status : CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST);
        } catch (const cl::Error&) {  // (nothing more to tell: the receiver's queue is what fails)
        }
        lock.lock();
    }
}

}  // namespace clsph::cl_rt
