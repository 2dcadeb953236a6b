#include "cl/quirks.hpp"
#include "device/sizing.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace clsph::cl_rt {
namespace {
bool contains_ci(std::string hay, std::string needle) {
    auto low = [](std::string& s) {
        for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    };
    low(hay);
    low(needle);
    return hay.find(needle) != std::string::npos;
}
}  // namespace

Quirks quirks_for(const DeviceInfo& info) {
    Quirks q;
    const bool rusticl = contains_ci(info.platform, "rusticl");
    const bool nvidia = contains_ci(info.platform, "nvidia") || contains_ci(info.vendor, "nvidia");
    // Evidence: rusticl on Mesa 22.3.6 reports CL_PROFILING_COMMAND_START/END of 0..3 ns for any
    // kernel. Later Mesa versions fixed it, but we cannot tell a fixed build by version string
    // reliably, so all rusticl devices are host-timed (the cost is a queue.finish per timed launch).
    q.fake_event_timestamps = rusticl;
    q.kernel_work_group_size_understated = rusticl;
    q.vectorises_work_items = rusticl;
    q.atomic_min_unreliable = rusticl;
    q.late_transfer_callbacks = nvidia;
    if (nvidia) q.interaction_options = "-cl-nv-maxrregcount=48";
    const bool pocl = contains_ci(info.platform, "portable computing language") || contains_ci(info.platform, "pocl");
    if (pocl) q.build_salt = "-DCLSPH_POCL_DEVICE=" + std::to_string(info.index);
    q.user_events_stop = pocl && info.name.rfind("basic", 0) == 0;
    // Keep 1 KiB of the reported local memory free for the driver (pocl and NVIDIA place kernel
    // arguments or barriers there on some versions).
    const std::size_t reported = static_cast<std::size_t>(info.local_memory);
    q.usable_local_memory = device::sizing::usable_local_memory(reported);
    return q;
}

}  // namespace clsph::cl_rt
