#include "multi/device_threads.hpp"

namespace clsph::multi {

DeviceThreads::DeviceThreads(std::size_t devices) : devices_(devices), errors_(devices) {
    for (std::size_t d = 1; d < devices; ++d) workers_.emplace_back([this, d] { loop(d); });
}

DeviceThreads::~DeviceThreads() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    start_.notify_all();
    for (auto& w : workers_) w.join();
}

void DeviceThreads::loop(std::size_t device) {
    std::size_t seen = 0;
    for (;;) {
        const std::function<void(std::size_t)>* work = nullptr;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            start_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            work = work_;
        }
        std::exception_ptr error;
        try {
            (*work)(device);
        } catch (...) {
            error = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            errors_[device] = error;
            if (--running_ == 0) done_.notify_one();
        }
    }
}

void DeviceThreads::run(const std::function<void(std::size_t)>& work) {
    if (devices_ == 0) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        work_ = &work;
        running_ = workers_.size();
        ++generation_;
        for (auto& e : errors_) e = nullptr;
    }
    start_.notify_all();
    try {
        work(0);
    } catch (...) {
        errors_[0] = std::current_exception();  // the workers never touch entry 0
    }
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return running_ == 0; });
    for (auto& e : errors_)
        if (e) std::rethrow_exception(e);
}

}  // namespace clsph::multi
