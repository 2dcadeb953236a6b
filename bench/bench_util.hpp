// What the benchmark tools share: summary statistics of repeated timings, timing a piece of device
// work by its launches' events (or host clocks where the driver's events lie), and table cells.
#pragma once
#include "cl/device.hpp"

#include <functional>
#include <string>
#include <vector>

namespace clsph::bench {

struct Summary {
    double median = 0, min = 0, max = 0;
};
Summary summarize(std::vector<double> samples);

// Seconds of device time the launches made by `work` took: the sum of their event times, or host
// clocks around each launch where quirks().fake_event_timestamps (Device::launch handles both).
// `prepare` runs first, untimed (e.g. restoring unsorted input).
double time_launches(cl_rt::Device& dev, const std::function<void()>& work, const std::function<void()>& prepare = {});

// Seconds a clEnqueueCopyBuffer of `bytes` takes on the device (its event, or host clocks).
double time_copy(cl_rt::Device& dev, const cl_rt::Buffer& src, cl_rt::Buffer& dst, std::size_t bytes);

// Host seconds from an idle queue to the end of `work` (what a caller waits, launch costs included).
double time_host(cl_rt::Device& dev, const std::function<void()>& work);

// Runs `once` `warmup` times, then `repeats` times, and summarizes what the timed runs returned.
Summary measure(int warmup, int repeats, const std::function<double()>& once);

// "12.3 (12.1-12.9)": a rate from the fastest/slowest run (scale divided by seconds).
std::string rate_cell(const Summary& seconds, double scale, int precision = 2);

std::string header(cl_rt::Device& dev);        // "### <device>" plus platform, driver, OpenCL C, size
std::string today();                            // YYYY-MM-DD (UTC)
std::string bytes_label(std::size_t bytes);     // 1 KiB, 64 MiB, ...

}  // namespace clsph::bench
