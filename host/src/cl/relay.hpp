// Copies from one device to another that the receiver's compute queue waits for, with no host
// thread waiting on either device: what the step ahead on several devices needs (docs/
// multi_device.md, "The step ahead on several devices").
//
// Within one context (one device opened as several slabs: OpenOptions::slabs) the receiver's
// queue waits for a marker of the sender's and copies device to device. Across contexts (other
// devices, other vendors: events of one context mean nothing to another) the sender reads into
// pinned host memory on its compute queue; the read's completion callback wakes the relay's
// thread, which then enqueues the write on a queue of the receiver's that the relay keeps for it
// (not the transfer queue: the reads of later steps' records wait there; only once the data is in
// host memory, so no driver can take it too early; after a marker of the receiver's compute queue
// placed when the copy was asked for, so that what was enqueued before it still reads the old
// data), and the write's completion sets a user event that the receiver's compute queue waits for. A failed read or write fails the user event, and
// with it the receiver's next commands: the host learns of it where it waits for them.
#pragma once
#include "cl/async.hpp"
#include "cl/cl.hpp"
#include "cl/memory.hpp"

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace clsph::cl_rt {

class Device;

class Relay {
public:
    Relay() = default;
    // Waits for the copies in flight (a copy whose source never completes: two seconds, then its
    // receiver's queue is failed).
    ~Relay();
    Relay(const Relay&) = delete;
    Relay& operator=(const Relay&) = delete;

    // One contiguous range of a buffer of the sender to a range of a buffer of the receiver.
    struct Piece {
        const Buffer* src;
        Buffer* dst;
        std::size_t bytes, src_offset, dst_offset;
    };
    // The pieces, after what `from`'s compute queue holds now, into `to`, before what `to`'s
    // compute queue is given next. `staging` (across contexts: pinned memory of `from`'s context,
    // grown to the pieces' total) must stay untouched until `to`'s queue has passed this point.
    void copy(Device& from, Device& to, const std::vector<Piece>& pieces, PinnedHost& staging);
    static bool same_context(Device& a, Device& b);

private:
    struct Job {
        cl::Event ready;                 // the sender's last read
        cl::UserEvent done;              // the receiver's compute queue waits for it
        cl::Event after;                 // the receiver's compute queue where the copy was asked for
        Device* to = nullptr;
        std::vector<Piece> pieces;
        const unsigned char* staged = nullptr;
        cl_int status = CL_QUEUED;       // the read's, once its callback came (CL_COMPLETE or < 0)
        bool polled = false;             // no callback: the relay's thread looks at the read's status
        Device* from = nullptr;
        bool writing = false;            // the write enqueued: `written` is its (last) event
        cl::Event written;
        cl_int written_status = CL_QUEUED;
        bool write_polled = false;
    };
    void run();  // the relay's thread
    void start();
    cl::CommandQueue& queue_for(Device* from, Device& to);  // the relay's thread only
    void watch(const cl::Event& event, const std::shared_ptr<Job>& job, cl_int Job::*status, bool Job::*polled, bool late);
    std::map<std::pair<Device*, Device*>, cl::CommandQueue> queues_;

    struct Shared {
        std::mutex m;
        std::condition_variable cv;
        std::deque<std::shared_ptr<Job>> jobs;
        bool stop = false;
        std::chrono::steady_clock::time_point give_up;  // stopping: when to leave what is left
    };
    std::shared_ptr<Shared> shared_;
    std::thread thread_;
};

}  // namespace clsph::cl_rt
