#include "cl/memory.hpp"

#include "cl/errors.hpp"
#include "cl/faults.hpp"
#include "clsph/error.hpp"

#include <sstream>

namespace clsph::cl_rt {
namespace {
std::string mib(std::size_t b) {
    std::ostringstream o;
    o.precision(1);
    o << std::fixed << static_cast<double>(b) / (1024.0 * 1024.0) << " MiB";
    return o.str();
}
}  // namespace

MemoryTracker::MemoryTracker(cl::Context context, std::string device_label, std::size_t global_memory,
                             std::size_t max_allocation, FaultInjector* faults)
    : context_(std::move(context)), label_(std::move(device_label)), faults_(faults), state_(std::make_shared<State>()) {
    state_->global_memory = global_memory;
    state_->max_allocation = max_allocation;
}

Buffer MemoryTracker::allocate(std::size_t bytes, const std::string& what, cl_mem_flags flags) {
    if (bytes == 0) bytes = 16;  // OpenCL forbids empty buffers; a small one keeps kernels' args valid
    auto& c = state_->counters;
    if (bytes > state_->max_allocation)
        throw OutOfDeviceMemory("device " + label_ + ": buffer '" + what + "' needs " + mib(bytes) +
                                " but the largest single allocation allowed is " + mib(state_->max_allocation));
    if (c.current + bytes > state_->global_memory)
        throw OutOfDeviceMemory("device " + label_ + ": buffer '" + what + "' needs " + mib(bytes) + " but only " +
                                mib(state_->global_memory - c.current) + " of " + mib(state_->global_memory) +
                                " remain (" + mib(c.current) + " already held by clsph)");
    cl_int err = CL_SUCCESS;
    const std::string doing = "allocating buffer '" + what + "' (" + mib(bytes) + ")";
    cl::Buffer buf = guarded(doing, label_, [&] {
        if (faults_) faults_->before(testing::FaultCall::allocation, "clCreateBuffer");
        return cl::Buffer(context_, flags, bytes, nullptr, &err);
    });
    check(err, doing, label_);
    c.current += bytes;
    c.buffers += 1;
    state_->live[what] += bytes;
    if (c.current > c.peak) {
        c.peak = c.current;
        state_->at_peak = state_->live;
    }
    return Buffer(std::move(buf), bytes, state_, what);
}

Buffer::Buffer(cl::Buffer buffer, std::size_t bytes, std::shared_ptr<MemoryTracker::State> state, std::string what)
    : buffer_(std::move(buffer)), bytes_(bytes), state_(std::move(state)), what_(std::move(what)) {}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept
    : buffer_(std::move(o.buffer_)), bytes_(o.bytes_), state_(std::move(o.state_)), what_(std::move(o.what_)) {
    o.bytes_ = 0;
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        buffer_ = std::move(o.buffer_);
        bytes_ = o.bytes_;
        state_ = std::move(o.state_);
        what_ = std::move(o.what_);
        o.bytes_ = 0;
    }
    return *this;
}

void Buffer::swap(Buffer& other) noexcept {
    std::swap(buffer_, other.buffer_);
    std::swap(bytes_, other.bytes_);
    std::swap(state_, other.state_);
    std::swap(what_, other.what_);
}

void Buffer::release() noexcept {
    if (state_ && bytes_) {
        state_->counters.current -= bytes_;
        state_->counters.buffers -= 1;
        const auto it = state_->live.find(what_);
        if (it != state_->live.end() && (it->second -= bytes_) == 0) state_->live.erase(it);
    }
    bytes_ = 0;
    state_.reset();
    buffer_ = cl::Buffer();
}

}  // namespace clsph::cl_rt
