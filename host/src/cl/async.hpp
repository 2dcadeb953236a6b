// Waiting for device work without spinning. Commands are enqueued without blocking and their events
// collected in an EventSet; wait() flushes the queues involved and sleeps on a condition variable
// that the events' completion callbacks signal (clFinish and blocking reads busy-wait a CPU core on
// NVIDIA's OpenCL). Pinned host memory (CL_MEM_ALLOC_HOST_PTR, mapped once) is what transfers
// between devices are staged through: the foundation's transfer benchmark measured ~55 GB/s into
// and out of it on an H200, against ~5 GB/s for pageable memory.
#pragma once
#include "cl/cl.hpp"

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

namespace clsph::cl_rt {

class Device;

class EventSet {
public:
    void add(Device& device, cl::Event event);
    bool empty() const { return events_.empty(); }
    std::vector<cl::Event> events_of(const Device& device) const;
    // How to wait: sleep on the events' completion callbacks; poll their status, sleeping 20 us
    // between looks; or clWaitForEvents (which spins a core on NVIDIA).
    enum class Mode { callbacks, poll, block };
    // Blocks until every event has completed; throws DeviceError naming `what` and the device when
    // a command failed. The set is empty afterwards. Mode callbacks becomes poll where a device's
    // callbacks come late (Quirks::late_transfer_callbacks).
    void wait(const std::string& what, Mode mode = Mode::callbacks);

private:
    mutable std::mutex mutex_;  // add() may be called from one host thread per device
    std::vector<cl::Event> events_;
    std::vector<Device*> devices_;  // of each event, for the flush and the error message
};

// Host memory of one device's context that the driver can copy to and from at full speed (and that
// other contexts' devices read and write as ordinary host memory). Grows, keeping nothing.
class PinnedHost {
public:
    PinnedHost() = default;
    ~PinnedHost();
    PinnedHost(const PinnedHost&) = delete;
    PinnedHost& operator=(const PinnedHost&) = delete;

    // At least `bytes` (with `headroom` extra when it has to grow); returns true if it reallocated.
    bool reserve(Device& device, std::size_t bytes, double headroom = 0.25);
    unsigned char* data() { return data_; }
    const unsigned char* data() const { return data_; }
    std::size_t bytes() const { return bytes_; }

private:
    void release();
    Device* device_ = nullptr;
    cl::Buffer buffer_;
    unsigned char* data_ = nullptr;
    std::size_t bytes_ = 0;
};

// A small array in pinned host memory: the target of the reads (and the source of the writes) the
// host waits for every step — counters, counts, reductions, searched positions. NVIDIA stages
// transfers to and from pageable memory through a host thread, which measured 0.1-0.3 ms before
// the next command starts on the device. resize() keeps nothing when it has to grow.
template <class T>
class PinnedArray {
public:
    void resize(Device& device, std::size_t n) {
        pinned_.reserve(device, std::max<std::size_t>(n, 1) * sizeof(T), 0.5);
        n_ = n;
    }
    T* data() { return reinterpret_cast<T*>(pinned_.data()); }
    const T* data() const { return reinterpret_cast<const T*>(pinned_.data()); }
    std::size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    T& operator[](std::size_t i) { return data()[i]; }
    const T& operator[](std::size_t i) const { return data()[i]; }
    const T* begin() const { return data(); }
    const T* end() const { return data() + n_; }
    const T& front() const { return data()[0]; }
    const T& back() const { return data()[n_ - 1]; }

private:
    PinnedHost pinned_;
    std::size_t n_ = 0;
};

}  // namespace clsph::cl_rt
