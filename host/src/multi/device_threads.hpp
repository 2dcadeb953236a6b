// One host thread per device for the enqueue sequences of a step's phases. Enqueueing is not free
// (on NVIDIA ~10 us per launch, and a write from memory pinned in another device's context holds
// the calling thread until it is done): with one host thread feeding the devices in turn, the last
// device starts each phase 0.1-0.3 ms after the first (trace of two H200s). The caller's thread
// takes device 0; workers take the others.
#pragma once
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace clsph::multi {

class DeviceThreads {
public:
    explicit DeviceThreads(std::size_t devices);
    ~DeviceThreads();
    DeviceThreads(const DeviceThreads&) = delete;
    DeviceThreads& operator=(const DeviceThreads&) = delete;

    // Runs work(d) for every device d at once and returns when all are done. If any threw, the
    // exception of the lowest-numbered device is rethrown here (after all have finished).
    void run(const std::function<void(std::size_t)>& work);

private:
    void loop(std::size_t device);
    std::size_t devices_;
    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable start_, done_;
    const std::function<void(std::size_t)>* work_ = nullptr;
    std::size_t generation_ = 0, running_ = 0;
    bool stop_ = false;
    std::vector<std::exception_ptr> errors_;
};

}  // namespace clsph::multi
