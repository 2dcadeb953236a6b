#include "cl/profiler.hpp"

namespace clsph::cl_rt {

void Profiler::collect() {
    for (auto& p : pending_) {
        p.event.wait();
        const auto start = p.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        const auto end = p.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        add_seconds(p.name, end > start ? static_cast<double>(end - start) * 1e-9 : 0.0);
        if (tracing_) trace_.push_back({p.name, start, end});
    }
    pending_.clear();
}

}  // namespace clsph::cl_rt
