#include "cl/profiler.hpp"

namespace clsph::cl_rt {

void Profiler::fold(Pending& p) {
    const auto start = p.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = p.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    add_seconds(p.name, end > start ? static_cast<double>(end - start) * 1e-9 : 0.0);
    if (tracing_) trace_.push_back({p.name, start, end});
}

void Profiler::collect() {
    for (auto& p : pending_) {
        p.event.wait();
        fold(p);
    }
    pending_.clear();
}

void Profiler::collect_finished() {
    std::size_t done = 0;
    for (; done < pending_.size(); ++done) {
        cl_int status = CL_QUEUED;
        if (clGetEventInfo(pending_[done].event(), CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr) !=
                CL_SUCCESS ||
            status != CL_COMPLETE)
            break;
        fold(pending_[done]);
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(done));
}

}  // namespace clsph::cl_rt
