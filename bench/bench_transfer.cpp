// clsph-bench-transfer: how fast data moves between two devices, the ways the multi-device driver
// moves it (docs/multi_device.md, "Link"):
//   (a) staged through pinned host memory across two contexts: read from device A into a
//       CL_MEM_ALLOC_HOST_PTR buffer mapped once, then write from it into device B (with one device
//       selected, B is the same device opened in a second context); pinned memory of B's context
//       and plain pageable memory are shown for comparison;
//   (b) clEnqueueCopyBuffer within one context holding both devices (when they share a platform):
//       the source is written on A, the copy runs on B's queue; with one device, a copy within it.
// Sizes 1 KiB to 256 MiB; MB/s counts the bytes moved once (10^6 bytes per MB). Times are host
// clocks from an idle queue to the data having arrived (what a caller waits); median of repeats
// after warm-up; every size's result is read back and checked once.
#include "bench_util.hpp"

#include "cl/errors.hpp"
#include "clsph/devices.hpp"
#include "clsph/error.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

using namespace clsph;
using u32 = std::uint32_t;

namespace {

struct Options {
    std::string devices;
    int max_log2 = 28;
    int warmup = 3, repeats = 15;
};

double host_seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string mbps(const bench::Summary& s, std::size_t bytes) { return bench::rate_cell(s, static_cast<double>(bytes) * 1e-6, 0); }

std::string micros(const bench::Summary& s) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(1) << s.median * 1e6;
    return o.str();
}

// A CL_MEM_ALLOC_HOST_PTR buffer of `bytes` in `dev`'s context, mapped once for the whole run (the
// driver can then DMA straight from/to it).
struct Pinned {
    cl::Buffer buffer;
    cl::CommandQueue queue;
    void* ptr = nullptr;
    Pinned(cl_rt::Device& dev, std::size_t bytes) : queue(dev.queue()) {
        cl_int err = CL_SUCCESS;
        buffer = cl::Buffer(dev.context(), CL_MEM_ALLOC_HOST_PTR | CL_MEM_READ_WRITE, bytes, nullptr, &err);
        cl_rt::check(err, "allocating pinned host memory", dev.label());
        ptr = queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, bytes, nullptr, nullptr, &err);
        cl_rt::check(err, "mapping pinned host memory", dev.label());
    }
    ~Pinned() {
        queue.enqueueUnmapMemObject(buffer, ptr);
        queue.finish();
    }
    Pinned(const Pinned&) = delete;
    Pinned& operator=(const Pinned&) = delete;
};

void check_prefix(cl_rt::Device& dev, const cl_rt::Buffer& got, const std::vector<u32>& want, std::size_t bytes,
                  const std::string& what) {
    std::vector<u32> v(bytes / sizeof(u32));
    dev.read(got, v.data(), v.size());
    if (std::memcmp(v.data(), want.data(), bytes) != 0) throw Error("validation failed: " + what + " of " + bench::bytes_label(bytes));
}

void staged(cl_rt::Device& a, cl_rt::Device& b, const Options& o, const std::vector<std::size_t>& sizes) {
    const std::size_t max_bytes = sizes.back();
    std::vector<u32> pattern(max_bytes / sizeof(u32));
    for (std::size_t i = 0; i < pattern.size(); ++i) pattern[i] = static_cast<u32>(i * 2654435761u) ^ 0x5bd1e995u;
    auto src = a.alloc(max_bytes, "transfer source");
    auto dst = b.alloc(max_bytes, "transfer destination");
    a.write(src, pattern.data(), pattern.size());
    Pinned pin_a(a, max_bytes), pin_b(b, max_bytes);
    std::vector<u32> pageable(pattern.size());

    auto read_a = [&](void* host, std::size_t bytes) {
        cl_rt::check(a.queue().enqueueReadBuffer(src.get(), CL_TRUE, 0, bytes, host), "reading", a.label());
    };
    auto write_b = [&](const void* host, std::size_t bytes) {
        cl_rt::check(b.queue().enqueueWriteBuffer(dst.get(), CL_TRUE, 0, bytes, host), "writing", b.label());
    };
    auto timed = [&](const std::function<void()>& f) {
        return bench::measure(o.warmup, o.repeats, [&] { return host_seconds(f); });
    };

    std::cout << "(a) staged through host memory: A = " << a.label() << ", B = " << b.label()
              << (a.cl_device()() == b.cl_device()() ? " (the same device in a second context)" : "") << "\n\n"
              << "| size | A to pinned MB/s | pinned to B MB/s | A to B via pinned(A) MB/s | A to B via pinned(A) us | "
                 "A to B via pinned(B) MB/s | A to B via pageable MB/s |\n|---|---|---|---|---|---|---|\n";
    for (std::size_t bytes : sizes) {
        const auto d2h = timed([&] { read_a(pin_a.ptr, bytes); });
        const auto h2d = timed([&] { write_b(pin_a.ptr, bytes); });
        const auto via_a = timed([&] { read_a(pin_a.ptr, bytes); write_b(pin_a.ptr, bytes); });
        b.fill(dst, u32{0}, max_bytes / sizeof(u32));
        read_a(pin_a.ptr, bytes);
        write_b(pin_a.ptr, bytes);
        check_prefix(b, dst, pattern, bytes, "staged copy");
        const auto via_b = timed([&] { read_a(pin_b.ptr, bytes); write_b(pin_b.ptr, bytes); });
        const auto via_pageable = timed([&] { read_a(pageable.data(), bytes); write_b(pageable.data(), bytes); });
        std::cout << "| " << bench::bytes_label(bytes) << " | " << mbps(d2h, bytes) << " | " << mbps(h2d, bytes) << " | "
                  << mbps(via_a, bytes) << " | " << micros(via_a) << " | " << mbps(via_b, bytes) << " | "
                  << mbps(via_pageable, bytes) << " |" << std::endl;
    }
}

// (b): one context holding both devices (or the one device), source written on A, copy on B's queue.
void shared_context(const std::vector<cl::Device>& devs, const std::string& what, const Options& o,
                    const std::vector<std::size_t>& sizes) {
    cl_int err = CL_SUCCESS;
    cl::Context ctx(devs, nullptr, nullptr, nullptr, &err);
    cl_rt::check(err, "creating a context for " + what);
    cl::CommandQueue qa(ctx, devs.front(), 0, &err);
    cl_rt::check(err, "creating a queue");
    cl::CommandQueue qb(ctx, devs.back(), 0, &err);
    cl_rt::check(err, "creating a queue");
    const std::size_t max_bytes = sizes.back();
    cl::Buffer src(ctx, CL_MEM_READ_WRITE, max_bytes, nullptr, &err);
    cl_rt::check(err, "allocating the source");
    cl::Buffer dst(ctx, CL_MEM_READ_WRITE, max_bytes, nullptr, &err);
    cl_rt::check(err, "allocating the destination");
    std::cout << "\n(b) clEnqueueCopyBuffer in one context, " << what << "\n\n"
              << "| size | MB/s | us |\n|---|---|---|\n";
    for (std::size_t bytes : sizes) {
        const u32 value = 0xA5000000u ^ static_cast<u32>(bytes);
        auto once = [&] {
            // The source is produced on A (a fill there), so the copy on B has to fetch it from A.
            cl_rt::check(qa.enqueueFillBuffer(src, value, 0, bytes), "filling the source on A");
            cl_rt::check(qa.finish(), "waiting for A");
            return host_seconds([&] {
                cl_rt::check(qb.enqueueCopyBuffer(src, dst, 0, 0, bytes), "copying on B");
                cl_rt::check(qb.finish(), "waiting for B");
            });
        };
        const auto t = bench::measure(o.warmup, o.repeats, once);
        std::vector<u32> got(bytes / sizeof(u32));
        cl_rt::check(qb.enqueueReadBuffer(dst, CL_TRUE, 0, bytes, got.data()), "reading back");
        for (u32 x : got)
            if (x != value) throw Error("validation failed: shared-context copy of " + bench::bytes_label(bytes));
        std::cout << "| " << bench::bytes_label(bytes) << " | " << mbps(t, bytes) << " | " << micros(t) << " |" << std::endl;
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph-bench-transfer: device-to-device transfer bandwidth and latency"};
    Options o;
    o.devices = default_device_spec();
    app.add_option("--devices", o.devices, "the first two selected devices are A and B (one device: A = B)");
    app.add_option("--max-log2", o.max_log2, "largest transfer, log2 of bytes (default 28: 256 MiB)")->check(CLI::Range(10, 31));
    app.add_option("--warmup", o.warmup, "untimed runs first")->check(CLI::Range(0, 100));
    app.add_option("--repeats", o.repeats, "timed runs (median, min, max reported)")->check(CLI::Range(1, 1000));
    CLI11_PARSE(app, argc, argv);
    try {
        auto devices = cl_rt::open_devices(o.devices);
        std::vector<std::size_t> sizes;
        for (int lg = 10; lg <= o.max_log2; lg += 2) sizes.push_back(std::size_t{1} << lg);
        cl_rt::Device& a = *devices.front();
        std::unique_ptr<cl_rt::Device> second_context;
        cl_rt::Device* b = devices.size() > 1 ? devices[1].get() : nullptr;
        if (!b) {
            cl_int err = CL_SUCCESS;
            cl::Context ctx(a.cl_device(), nullptr, nullptr, nullptr, &err);
            cl_rt::check(err, "creating a second context", a.label());
            second_context = std::make_unique<cl_rt::Device>(a.info(), a.cl_device(), ctx, cl_rt::OpenOptions{});
            b = second_context.get();
        }
        std::cout << "## clsph-bench-transfer, " << bench::today() << "\n\n`";
        for (int i = 0; i < argc; ++i) std::cout << (i ? " " : "") << argv[i];
        std::cout << "`; median (min-max) of " << o.repeats << " runs after " << o.warmup
                  << " warm-up runs, host clocks\n\n" << bench::header(a) << "\n";
        if (b != second_context.get()) std::cout << bench::header(*b) << "\n";
        staged(a, *b, o, sizes);
        if (b == second_context.get())
            shared_context({a.cl_device()}, "within one device (" + a.label() + ")", o, sizes);
        else if (a.info().platform == b->info().platform)
            shared_context({a.cl_device(), b->cl_device()}, "A and B (" + a.info().platform + ")", o, sizes);
        else
            std::cout << "\n(b) skipped: A and B are on different platforms, so no context holds both\n";
    } catch (const Error& e) {
        std::cerr << "clsph-bench-transfer: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
