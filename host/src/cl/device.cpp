#include "cl/device.hpp"

#include "cl/errors.hpp"
#include "clsph/error.hpp"

#include <algorithm>

#include <chrono>

namespace clsph::cl_rt {

std::vector<cl::Device> platform_devices(const cl::Platform& platform);  // devices.cpp

namespace {
// Where a device's builds are salted (Quirks::build_salt: pocl), each slab of it gets binaries of
// its own too: pocl 3.1's shared-library count breaks as soon as two openings of one device run
// the same kernel (four slabs of one pthread device stopped in its assertion every time).
std::string slab_salt(const std::string& salt, std::size_t slab) {
    if (salt.empty() || slab == 0) return salt;
    return salt + " -DCLSPH_SLAB=" + std::to_string(slab);
}
}  // namespace

Device::Device(DeviceInfo info, cl::Device device, cl::Context context, const OpenOptions& options)
    : info_(std::move(info)),
      label_("#" + std::to_string(info_.index) + " " + info_.name + " (" + info_.platform + ")" + options.label_suffix),
      quirks_(quirks_for(info_)),
      device_(std::move(device)),
      context_(std::move(context)),
      faults_(std::make_unique<FaultInjector>(options.faults)),
      memory_(context_, label_, static_cast<std::size_t>(info_.global_memory),
              static_cast<std::size_t>(info_.max_allocation), faults_.get()),
      programs_(context_, device_, label_, faults_.get(), slab_salt(quirks_.build_salt, options.slab)),
      profiler_(quirks_.fake_event_timestamps) {
    cl_int err = CL_SUCCESS;
    // Queues always allow profiling (its cost is negligible on the drivers we know), so timing can
    // be switched on at any point; the balancer needs event times every step anyway.
    const cl_command_queue_properties props = quirks_.fake_event_timestamps ? 0 : CL_QUEUE_PROFILING_ENABLE;
    guarded("creating the command queues", label_, [&] {
        queue_ = cl::CommandQueue(context_, device_, props, &err);
        check(err, "creating the command queue", label_);
        transfer_queue_ = cl::CommandQueue(context_, device_, props, &err);
        check(err, "creating the transfer queue", label_);
    });
    profiler_.enable(options.profiling);
}

template <class F>
void Device::call(std::optional<testing::FaultCall> kind, const char* cl_name, const char* doing, F&& f,
                  const std::string* kernel) {
    try {
        if (kind) faults_->before(*kind, cl_name);
        const cl_int err = f();
        if (err != CL_SUCCESS) throw cl::Error(err, cl_name);
    } catch (const cl::Error& e) {
        // The message is made only here: launches are the hot path.
        throw device_error(e, kernel ? std::string(doing) + " '" + *kernel + "'" : std::string(doing), label_);
    }
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
        call(std::nullopt, "clFinish", "waiting before kernel", [&] { return queue_.finish(); }, &name);
        const auto t0 = std::chrono::steady_clock::now();
        call(
            testing::FaultCall::enqueue, "clEnqueueNDRangeKernel", "launching kernel",
            [&] { return queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(padded), cl::NDRange(local)); }, &name);
        call(std::nullopt, "clFinish", "running kernel", [&] { return queue_.finish(); }, &name);
        profiler_.add_seconds(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        return;
    }
    cl::Event ev;
    call(
        testing::FaultCall::enqueue, "clEnqueueNDRangeKernel", "launching kernel",
        [&] {
            return queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(padded), cl::NDRange(local), nullptr,
                                               profiler_.enabled() ? &ev : nullptr);
        },
        &name);
    if (profiler_.enabled()) profiler_.add_event(name, std::move(ev));
}

void Device::flush() {
    call(std::nullopt, "clFlush", "submitting the queue", [&] { return queue_.flush(); });
}

void Device::finish() {
    call(std::nullopt, "clFinish", "waiting for the transfer queue", [&] { return transfer_queue_.finish(); });
    call(std::nullopt, "clFinish", "waiting for the queue", [&] { return queue_.finish(); });
}

void Device::write_bytes(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset) {
    call(std::nullopt, "clEnqueueWriteBuffer", "writing a buffer",
         [&] { return queue_.enqueueWriteBuffer(dst.get(), CL_TRUE, offset, bytes, src); });
}

void Device::read_bytes(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset) {
    call(testing::FaultCall::read, "clEnqueueReadBuffer", "reading a buffer",
         [&] { return queue_.enqueueReadBuffer(src.get(), CL_TRUE, offset, bytes, dst); });
}

void Device::read_async(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset, EventSet& done, On on) {
    if (!bytes) return;
    cl::Event ev;
    call(testing::FaultCall::read, "clEnqueueReadBuffer", "reading a buffer", [&] {
        return (on == On::transfer ? transfer_queue_ : queue_).enqueueReadBuffer(src.get(), CL_FALSE, offset, bytes, dst, nullptr, &ev);
    });
    if (profiler_.enabled() && !profiler_.host_timed()) profiler_.add_event("transfer.read", ev);
    done.add(*this, std::move(ev));
}

void Device::write_async(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset, EventSet& done, On on) {
    if (!bytes) return;
    cl::Event ev;
    call(std::nullopt, "clEnqueueWriteBuffer", "writing a buffer", [&] {
        return (on == On::transfer ? transfer_queue_ : queue_).enqueueWriteBuffer(dst.get(), CL_FALSE, offset, bytes, src, nullptr, &ev);
    });
    if (profiler_.enabled() && !profiler_.host_timed()) profiler_.add_event("transfer.write", ev);
    done.add(*this, std::move(ev));
}

void Device::barrier(const EventSet& after) {
    std::vector<cl::Event> mine = after.events_of(*this);
    if (mine.empty()) return;
    call(std::nullopt, "clFlush", "submitting the transfer queue", [&] { return transfer_queue_.flush(); });
    call(std::nullopt, "clEnqueueBarrierWithWaitList", "ordering the compute queue after transfers",
         [&] { return queue_.enqueueBarrierWithWaitList(&mine); });
}

void Device::fill_bytes(Buffer& dst, const void* pattern, std::size_t pattern_size, std::size_t bytes,
                        std::size_t offset) {
    call(std::nullopt, "clEnqueueFillBuffer", "filling a buffer",
         [&] { return clEnqueueFillBuffer(queue_(), dst.get()(), pattern, pattern_size, offset, bytes, 0, nullptr, nullptr); });
}

void Device::copy(const Buffer& src, Buffer& dst, std::size_t bytes, std::size_t src_offset, std::size_t dst_offset) {
    if (bytes == 0) return;
    call(std::nullopt, "clEnqueueCopyBuffer", "copying a buffer",
         [&] { return queue_.enqueueCopyBuffer(src.get(), dst.get(), src_offset, dst_offset, bytes); });
}

namespace {
void apply(DeviceInfo& info, const OpenOptions& options) {
    if (options.max_allocation) info.max_allocation = std::min<std::uint64_t>(info.max_allocation, options.max_allocation);
}
}  // namespace

std::vector<DeviceInfo> selected_infos(const std::string& spec, const OpenOptions& options) {
    const auto all = list_devices();
    std::vector<DeviceInfo> out;
    for (std::size_t i : select_devices(all, spec)) {
        out.push_back(all[i]);
        apply(out.back(), options);
    }
    return out;
}

std::vector<std::unique_ptr<Device>> open_devices(const std::string& spec, const OpenOptions& options) {
    const auto infos = list_devices();
    const auto chosen = select_devices(infos, spec);
    if (!options.slabs.empty() && options.slabs.size() != chosen.size())
        throw Error("opening devices: slabs given for " + std::to_string(options.slabs.size()) + " devices, but '" + spec +
                    "' selects " + std::to_string(chosen.size()));
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
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        const std::size_t i = chosen[c];
        DeviceInfo info = infos[i];
        apply(info, options);
        cl::Device dev = all.at(i);
        cl_int err = CL_SUCCESS;
        const std::string name = "#" + std::to_string(i) + " " + info.name;
        cl::Context ctx = guarded("creating a context", name, [&] { return cl::Context(dev, nullptr, nullptr, nullptr, &err); });
        check(err, "creating a context", name);
        const std::size_t slabs = options.slabs.empty() ? 1 : std::max<std::size_t>(1, options.slabs[c]);
        for (std::size_t k = 0; k < slabs; ++k) {
            OpenOptions mine = options;  // the faults planned for this device only
            mine.faults.clear();
            for (const auto& f : options.faults)
                if (f.device == out.size()) mine.faults.push_back(f);
            if (slabs > 1) mine.label_suffix = " slab " + std::to_string(k + 1) + "/" + std::to_string(slabs);
            mine.slab = k;
            out.push_back(std::make_unique<Device>(info, dev, ctx, mine));
        }
    }
    return out;
}

}  // namespace clsph::cl_rt
