#include "cl/device.hpp"

#include "cl/errors.hpp"

#include <chrono>

namespace clsph::cl_rt {

std::vector<cl::Device> platform_devices(const cl::Platform& platform);  // devices.cpp

Device::Device(DeviceInfo info, cl::Device device, cl::Context context, const OpenOptions& options)
    : info_(std::move(info)),
      label_("#" + std::to_string(info_.index) + " " + info_.name + " (" + info_.platform + ")"),
      quirks_(quirks_for(info_)),
      device_(std::move(device)),
      context_(std::move(context)),
      memory_(context_, label_, static_cast<std::size_t>(info_.global_memory),
              static_cast<std::size_t>(info_.max_allocation)),
      programs_(context_, device_, label_),
      profiler_(quirks_.fake_event_timestamps) {
    cl_int err = CL_SUCCESS;
    // Queues always allow profiling (its cost is negligible on the drivers we know), so timing can
    // be switched on at any point; the balancer needs event times every step anyway.
    const cl_command_queue_properties props = quirks_.fake_event_timestamps ? 0 : CL_QUEUE_PROFILING_ENABLE;
    queue_ = cl::CommandQueue(context_, device_, props, &err);
    check(err, "creating command queue", label_);
    transfer_queue_ = cl::CommandQueue(context_, device_, props, &err);
    check(err, "creating the transfer queue", label_);
    profiler_.enable(options.profiling);
}

std::size_t Device::work_group_size(std::size_t cap) const {
    std::size_t limit = std::min(cap, info_.max_work_group_size);
    std::size_t p = 1;
    while (p * 2 <= limit) p *= 2;
    return p;
}

void Device::launch(const std::string& name, cl::Kernel& kernel, std::size_t global, std::size_t local) {
    if (global == 0) return;
    const std::size_t padded = (global + local - 1) / local * local;
    if (profiler_.enabled() && profiler_.host_timed()) {
        queue_.finish();
        const auto t0 = std::chrono::steady_clock::now();
        check(queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(padded), cl::NDRange(local)),
              "launching kernel '" + name + "'", label_);
        queue_.finish();
        profiler_.add_seconds(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        return;
    }
    cl::Event ev;
    check(queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(padded), cl::NDRange(local), nullptr,
                                      profiler_.enabled() ? &ev : nullptr),
          "launching kernel '" + name + "'", label_);
    if (profiler_.enabled()) profiler_.add_event(name, std::move(ev));
}

void Device::flush() { check(queue_.flush(), "submitting the queue", label_); }

void Device::finish() {
    check(transfer_queue_.finish(), "waiting for the transfer queue", label_);
    check(queue_.finish(), "waiting for the queue", label_);
}

void Device::write_bytes(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset) {
    check(queue_.enqueueWriteBuffer(dst.get(), CL_TRUE, offset, bytes, src), "writing a buffer", label_);
}

void Device::read_bytes(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset) {
    check(queue_.enqueueReadBuffer(src.get(), CL_TRUE, offset, bytes, dst), "reading a buffer", label_);
}

void Device::read_async(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset, EventSet& done, On on) {
    if (!bytes) return;
    cl::Event ev;
    check((on == On::transfer ? transfer_queue_ : queue_).enqueueReadBuffer(src.get(), CL_FALSE, offset, bytes, dst, nullptr, &ev), "reading a buffer", label_);
    if (profiler_.enabled() && !profiler_.host_timed()) profiler_.add_event("transfer.read", ev);
    done.add(*this, std::move(ev));
}

void Device::write_async(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset, EventSet& done, On on) {
    if (!bytes) return;
    cl::Event ev;
    check((on == On::transfer ? transfer_queue_ : queue_).enqueueWriteBuffer(dst.get(), CL_FALSE, offset, bytes, src, nullptr, &ev), "writing a buffer", label_);
    if (profiler_.enabled() && !profiler_.host_timed()) profiler_.add_event("transfer.write", ev);
    done.add(*this, std::move(ev));
}

void Device::barrier(const EventSet& after) {
    std::vector<cl::Event> mine = after.events_of(*this);
    if (mine.empty()) return;
    check(transfer_queue_.flush(), "submitting the transfer queue", label_);
    check(queue_.enqueueBarrierWithWaitList(&mine), "ordering the compute queue after transfers", label_);
}

void Device::fill_bytes(Buffer& dst, const void* pattern, std::size_t pattern_size, std::size_t bytes,
                        std::size_t offset) {
    check(clEnqueueFillBuffer(queue_(), dst.get()(), pattern, pattern_size, offset, bytes, 0, nullptr, nullptr),
          "filling a buffer", label_);
}

void Device::copy(const Buffer& src, Buffer& dst, std::size_t bytes, std::size_t src_offset, std::size_t dst_offset) {
    if (bytes == 0) return;
    check(queue_.enqueueCopyBuffer(src.get(), dst.get(), src_offset, dst_offset, bytes), "copying a buffer", label_);
}

std::vector<std::unique_ptr<Device>> open_devices(const std::string& spec, const OpenOptions& options) {
    const auto infos = list_devices();
    const auto chosen = select_devices(infos, spec);
    // Map stable indices back to cl::Device objects by walking platforms in the same order.
    std::vector<cl::Platform> platforms;
    cl::Platform::get(&platforms);
    std::vector<std::pair<std::string, cl::Platform>> sorted;
    for (auto& p : platforms) sorted.emplace_back(p.getInfo<CL_PLATFORM_NAME>(), p);
    std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<cl::Device> all;
    for (auto& [name, p] : sorted) {
        const auto devs = platform_devices(p);
        all.insert(all.end(), devs.begin(), devs.end());
    }
    std::vector<std::unique_ptr<Device>> out;
    for (std::size_t i : chosen) {
        const auto& info = infos[i];
        cl::Device dev = all.at(i);
        cl_int err = CL_SUCCESS;
        cl::Context ctx(dev, nullptr, nullptr, nullptr, &err);
        check(err, "creating a context", "#" + std::to_string(i) + " " + info.name);
        out.push_back(std::make_unique<Device>(info, dev, ctx, options));
    }
    return out;
}

}  // namespace clsph::cl_rt
