// Device memory accounting: every device buffer of the engine is made here, so we know how many
// bytes each device holds (now and at peak) and can refuse a request, with needed vs available,
// before the driver fails in a less helpful way.
#pragma once
#include "cl/cl.hpp"

#include <cstddef>
#include <map>
#include <memory>
#include <string>

namespace clsph::cl_rt {

struct MemoryCounters {
    std::size_t current = 0;  // bytes held now by live Buffers
    std::size_t peak = 0;     // the most ever held at once
    std::size_t buffers = 0;  // live buffers
};

class Buffer;
class FaultInjector;

class MemoryTracker {
public:
    MemoryTracker(cl::Context context, std::string device_label, std::size_t global_memory,
                  std::size_t max_allocation, FaultInjector* faults = nullptr);
    // Allocates `bytes` (at least 1) named `what` (used in errors). Throws OutOfDeviceMemory before
    // asking the driver when the request exceeds the max allocation or the global memory left.
    Buffer allocate(std::size_t bytes, const std::string& what, cl_mem_flags flags = CL_MEM_READ_WRITE);
    const MemoryCounters& counters() const { return state_->counters; }
    std::size_t global_memory() const { return state_->global_memory; }
    std::size_t max_allocation() const { return state_->max_allocation; }
    void reset_peak() {
        state_->counters.peak = state_->counters.current;
        state_->at_peak = state_->live;
    }
    // Bytes held by name (the `what` of allocate), now and when the peak was reached: the measured
    // side of the memory plan (clsph/memory_plan.hpp), which names its buffers the same way.
    const std::map<std::string, std::size_t>& live() const { return state_->live; }
    const std::map<std::string, std::size_t>& at_peak() const { return state_->at_peak; }

    struct State {
        MemoryCounters counters;
        std::size_t global_memory = 0, max_allocation = 0;
        std::map<std::string, std::size_t> live, at_peak;
    };

private:
    cl::Context context_;
    std::string label_;
    FaultInjector* faults_;
    std::shared_ptr<State> state_;
};

// A tracked device buffer; releases its bytes from the tracker when destroyed. Move-only.
class Buffer {
public:
    Buffer() = default;
    Buffer(cl::Buffer buffer, std::size_t bytes, std::shared_ptr<MemoryTracker::State> state, std::string what = {});
    ~Buffer();
    Buffer(Buffer&&) noexcept;
    Buffer& operator=(Buffer&&) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    const cl::Buffer& get() const { return buffer_; }
    cl::Buffer& get() { return buffer_; }
    std::size_t bytes() const { return bytes_; }
    explicit operator bool() const { return bytes_ != 0; }
    void swap(Buffer& other) noexcept;

private:
    void release() noexcept;
    cl::Buffer buffer_;
    std::size_t bytes_ = 0;
    std::shared_ptr<MemoryTracker::State> state_;
    std::string what_;  // the tracker's name for it (its ledger)
};

}  // namespace clsph::cl_rt
