// One OpenCL device as the engine drives it: its context, an in-order compute queue and an in-order
// transfer queue (copies between devices run there while the compute queue works), its program
// cache, its memory accounting, its launch profiler and its quirks. Several Devices (of any vendors)
// live side by side in one process; nothing here is global.
#pragma once
#include "cl/async.hpp"
#include "cl/cl.hpp"
#include "cl/faults.hpp"
#include "cl/memory.hpp"
#include "cl/profiler.hpp"
#include "cl/program_cache.hpp"
#include "cl/quirks.hpp"
#include "clsph/devices.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace clsph::cl_rt {

struct OpenOptions {
    bool profiling = false;  // time every named launch (events, or host clocks where events lie)
    // Tests: OpenCL calls that fail (Fault::device is the position among the opened devices).
    std::vector<testing::Fault> faults = {};
    // Tests: each device's CL_DEVICE_MAX_MEM_ALLOC_SIZE as if its driver said so (0: as it says).
    std::uint64_t max_allocation = 0;
    // Slabs per selected device (empty: one each): a device of several slabs is opened that many
    // times, sharing one context, each with its own queues and labelled "slab k/n".
    std::vector<std::size_t> slabs = {};
    std::string label_suffix = {};  // set by open_devices() for each slab
    std::size_t slab = 0;           // which opening of its device this is (0: the first or only one)
};

class Device {
public:
    Device(DeviceInfo info, cl::Device device, cl::Context context, const OpenOptions& options);
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceInfo& info() const { return info_; }
    // "#1 pthread-skylake (Portable Computing Language)": how errors and logs name this device.
    const std::string& label() const { return label_; }
    const Quirks& quirks() const { return quirks_; }
    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    cl::CommandQueue& transfer_queue() { return transfer_queue_; }
    const cl::Device& cl_device() const { return device_; }
    MemoryTracker& memory() { return memory_; }
    ProgramCache& programs() { return programs_; }
    Profiler& profiler() { return profiler_; }
    FaultInjector& faults() { return *faults_; }

    Buffer alloc(std::size_t bytes, const std::string& what, cl_mem_flags flags = CL_MEM_READ_WRITE) {
        return memory_.allocate(bytes, what, flags);
    }
    cl::Kernel kernel(const std::string& file, const std::string& name, const std::string& options = {}) {
        return programs_.kernel(file, name, options);
    }

    // Enqueues a named 1-D launch; the global size is padded up to a multiple of `local` (OpenCL
    // 1.2 has no non-uniform work-groups), so kernels guard their index. Zero work is a no-op.
    void launch(const std::string& name, cl::Kernel& kernel, std::size_t global, std::size_t local);

    // The largest power-of-two work-group size <= cap this device allows.
    std::size_t work_group_size(std::size_t cap = 256) const;

    void finish();
    void flush();  // submits what is enqueued so the device starts on it

    // Typed upload/download helpers (blocking). Sizes in elements of T.
    template <class T>
    void write(Buffer& dst, const T* src, std::size_t count, std::size_t offset = 0) {
        if (count) write_bytes(dst, src, count * sizeof(T), offset * sizeof(T));
    }
    template <class T>
    void read(const Buffer& src, T* dst, std::size_t count, std::size_t offset = 0) {
        if (count) read_bytes(src, dst, count * sizeof(T), offset * sizeof(T));
    }
    template <class T>
    void fill(Buffer& dst, const T& value, std::size_t count, std::size_t offset = 0) {
        if (count) fill_bytes(dst, &value, sizeof(T), count * sizeof(T), offset * sizeof(T));
    }
    void copy(const Buffer& src, Buffer& dst, std::size_t bytes, std::size_t src_offset = 0, std::size_t dst_offset = 0);

    // Non-blocking transfers (bytes): the event goes into `done`, whose wait() is when the host
    // memory may be used (read) or reused (write).
    // On the transfer queue they run beside the compute queue's work: nothing orders them against
    // it, so they must not touch what it touches until an event says so (barrier()).
    enum class On { compute, transfer };
    void read_async(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset, EventSet& done,
                    On on = On::compute);
    void write_async(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset, EventSet& done,
                     On on = On::compute);
    // The compute queue's next commands wait for this device's events in `after` (e.g. writes on
    // the transfer queue).
    void barrier(const EventSet& after);

private:
    void write_bytes(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset);
    void read_bytes(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset);
    void fill_bytes(Buffer& dst, const void* pattern, std::size_t pattern_size, std::size_t bytes, std::size_t offset);
    // Runs an enqueue `f` (returning its cl_int) as the OpenCL call `cl_name`: a fault planned for
    // it, a cl::Error the bindings throw and an error code returned all become one DeviceError
    // naming what clsph was `doing` (and the `kernel`), the call and this device.
    template <class F>
    void call(std::optional<testing::FaultCall> kind, const char* cl_name, const char* doing, F&& f,
              const std::string* kernel = nullptr);

    DeviceInfo info_;
    std::string label_;
    Quirks quirks_;
    cl::Device device_;
    cl::Context context_;
    cl::CommandQueue queue_, transfer_queue_;
    std::unique_ptr<FaultInjector> faults_;  // before memory_ and programs_, which use it
    MemoryTracker memory_;
    ProgramCache programs_;
    Profiler profiler_;
};

// Opens the devices a selection spec names (see clsph/devices.hpp), one context and one in-order
// queue each, in the stable order (several slabs of a device: OpenOptions::slabs).
std::vector<std::unique_ptr<Device>> open_devices(const std::string& spec, const OpenOptions& options = {});

// What the spec selects, as open_devices() would open it (OpenOptions::max_allocation applied),
// without creating any context: what the memory plan is made for before anything is opened.
std::vector<DeviceInfo> selected_infos(const std::string& spec, const OpenOptions& options = {});

// What each opened device is (for the memory plan, clsph/memory_plan.hpp).
inline std::vector<DeviceInfo> infos(const std::vector<std::unique_ptr<Device>>& devices) {
    std::vector<DeviceInfo> out;
    for (const auto& d : devices) out.push_back(d->info());
    return out;
}

}  // namespace clsph::cl_rt
