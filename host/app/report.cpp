#include "report.hpp"

#include "progress.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

namespace clsph::app {

void print_summary(std::ostream& os, const RunTotals& t) {
    char text[512];
    const double steps = static_cast<double>(t.steps);
    const double ms_per_step = t.steps ? 1e3 * t.loop_seconds / steps : 0.0;
    const double rate = t.loop_seconds > 0 ? t.particle_steps / t.loop_seconds : 0.0;
    std::snprintf(text, sizeof text,
                  "clsph: %s at t = %.6g s: %llu steps in %s (set-up %s), %.3f ms/step, %.3g particle-steps/s\n",
                  t.outcome.c_str(), t.last.time, static_cast<unsigned long long>(t.steps),
                  format_duration(t.loop_seconds).c_str(), format_duration(t.setup_seconds).c_str(), ms_per_step, rate);
    os << text;
    os << "  particles: " << t.last.particles << " (" << t.fluid << " fluid), removed " << t.last.removed;
    if (t.last.created > 0) os << ", created " << t.last.created << " (inlets)";
    os << '\n';
    for (std::size_t i = 0; i < t.devices.size(); ++i) os << (i ? "           " : "  devices: ") << t.devices[i] << '\n';
    if (t.list_buffer > 0 && t.table_builds > 0) {  // the first build comes before the first step
        std::snprintf(text, sizeof text,
                      "  cell tables: built %zu times in %llu steps (every %.1f steps), kept while no particle could "
                      "move half the buffer (run.list_buffer %g)\n",
                      t.table_builds, static_cast<unsigned long long>(t.steps),
                      static_cast<double>(t.steps) / static_cast<double>(t.table_builds), t.list_buffer);
        os << text;
    }
    if (t.steps > 0) {
        const auto n = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
        if (t.steps_ahead == t.steps)
            std::snprintf(text, sizeof text, "  steps ahead of the host: all %llu", n(t.steps));
        else if (t.steps_ahead > 0)
            std::snprintf(text, sizeof text,
                          "  steps ahead of the host: %llu of %llu (%.1f %%; the others, which built the cell tables "
                          "or exchanged particles, waited for)",
                          n(t.steps_ahead), n(t.steps), 100.0 * static_cast<double>(t.steps_ahead) / steps);
        else
            std::snprintf(text, sizeof text, "  steps ahead of the host: none (each step waited for: "
                                             "docs/multi_device.md, \"The step ahead\", says when they run ahead)");
        os << text;
        if (t.steps_thrown > 0) os << "; " << t.steps_thrown << " more computed ahead and thrown away";
        os << '\n';
    }
    os << "  output: " << t.frames << " frame" << (t.frames == 1 ? "" : "s") << " in " << t.out_dir
       << "; open " << t.collection << " in ParaView (File > Open, then Apply)\n";
}

void print_profile(std::ostream& os, const std::vector<KernelTime>& per_device, std::uint64_t steps,
                   std::size_t devices) {
    // Simulation::profile() lists each device's kernels in turn; the table sums them by name.
    std::map<std::string, KernelTime> by_name;
    for (const auto& k : per_device) {
        auto& sum = by_name[k.name];
        sum.name = k.name;
        sum.calls += k.calls;
        sum.seconds += k.seconds;
    }
    std::vector<KernelTime> kernels;
    for (auto& entry : by_name) kernels.push_back(entry.second);
    std::sort(kernels.begin(), kernels.end(), [](const KernelTime& a, const KernelTime& b) { return a.seconds > b.seconds; });
    double total = 0.0;
    std::size_t calls = 0, width = 6;
    for (const auto& k : kernels) {
        total += k.seconds;
        calls += k.calls;
        width = std::max(width, k.name.size());
    }
    const int w = static_cast<int>(width);
    char text[512];
    std::snprintf(text, sizeof text, "%-*s %10s %12s %12s %7s\n", w, "kernel", "calls", "ms", "ms/call", "%");
    os << "\nper-kernel device time (" << steps << " steps"
       << (devices > 1 ? ", summed over " + std::to_string(devices) + " devices" : std::string()) << "):\n"
       << text;
    for (const auto& k : kernels) {
        const double ms = 1e3 * k.seconds;
        std::snprintf(text, sizeof text, "%-*s %10zu %12.2f %12.4f %7.1f\n", w, k.name.c_str(), k.calls, ms,
                      k.calls ? ms / static_cast<double>(k.calls) : 0.0, total > 0 ? 100.0 * k.seconds / total : 0.0);
        os << text;
    }
    std::snprintf(text, sizeof text, "%-*s %10zu %12.2f %12s %7.1f\n", w, "total", calls, 1e3 * total, "", 100.0);
    os << text;
    if (steps) {
        std::snprintf(text, sizeof text, "%.3f ms of kernel time per step\n", 1e3 * total / static_cast<double>(steps));
        os << text;
    }
    if (devices > 1 && steps) {
        // Each device's own total: how evenly the balancer spread the work.
        std::map<std::string, double> by_device;
        for (const auto& k : per_device) by_device[k.device] += k.seconds;
        for (const auto& [device, seconds] : by_device) {
            std::snprintf(text, sizeof text, "  %.3f ms/step on ", 1e3 * seconds / static_cast<double>(steps));
            os << text << device << '\n';
        }
    }
}

}  // namespace clsph::app
