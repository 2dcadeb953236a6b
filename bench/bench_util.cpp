#include "bench_util.hpp"

#include "cl/errors.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iomanip>
#include <sstream>

namespace clsph::bench {

Summary summarize(std::vector<double> samples) {
    Summary s;
    if (samples.empty()) return s;
    std::sort(samples.begin(), samples.end());
    const std::size_t m = samples.size() / 2;
    s.median = samples.size() % 2 ? samples[m] : 0.5 * (samples[m - 1] + samples[m]);
    s.min = samples.front();
    s.max = samples.back();
    return s;
}

double time_launches(cl_rt::Device& dev, const std::function<void()>& work, const std::function<void()>& prepare) {
    if (prepare) prepare();
    dev.finish();
    auto& prof = dev.profiler();
    prof.clear();
    prof.enable(true);
    work();
    double seconds = 0;
    for (const auto& [name, k] : prof.stats()) seconds += k.seconds;
    prof.enable(false);
    prof.clear();
    return seconds;
}

double time_host(cl_rt::Device& dev, const std::function<void()>& work) {
    dev.finish();
    const auto t0 = std::chrono::steady_clock::now();
    work();
    dev.finish();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double time_copy(cl_rt::Device& dev, const cl_rt::Buffer& src, cl_rt::Buffer& dst, std::size_t bytes) {
    if (dev.quirks().fake_event_timestamps)
        return time_host(dev, [&] { dev.copy(src, dst, bytes); });
    dev.finish();
    cl::Event ev;
    cl_rt::check(dev.queue().enqueueCopyBuffer(src.get(), dst.get(), 0, 0, bytes, nullptr, &ev), "copying a buffer",
                 dev.label());
    ev.wait();
    const auto start = ev.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = ev.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return static_cast<double>(end - start) * 1e-9;
}

Summary measure(int warmup, int repeats, const std::function<double()>& once) {
    for (int i = 0; i < warmup; ++i) (void)once();
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) t.push_back(once());
    return summarize(t);
}

std::string rate_cell(const Summary& seconds, double scale, int precision) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(precision);
    if (seconds.median <= 0) return "n/a";
    o << scale / seconds.median << " (" << scale / seconds.max << "-" << scale / seconds.min << ")";
    return o.str();
}

std::string header(cl_rt::Device& dev) {
    const auto& i = dev.info();
    std::ostringstream o;
    o << "### " << i.name << "\n\nplatform " << i.platform << ", driver " << i.driver_version << ", "
      << i.opencl_c_version << ", " << i.compute_units << " compute units, "
      << (i.global_memory >> 20) << " MiB\n";
    return o.str();
}

std::string today() {
    const std::time_t t = std::time(nullptr);
    char buf[16];
    std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&t));
    return buf;
}

std::string bytes_label(std::size_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB"};
    int u = 0;
    while (bytes >= 1024 && bytes % 1024 == 0 && u < 3) {
        bytes /= 1024;
        ++u;
    }
    return std::to_string(bytes) + " " + units[u];
}

}  // namespace clsph::bench
