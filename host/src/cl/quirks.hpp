// Driver facts that change how we drive a device, all in one place, each with its evidence.
#pragma once
#include "clsph/devices.hpp"
#include <cstddef>

namespace clsph::cl_rt {

struct Quirks {
    // Mesa rusticl 22.3 (Debian 12) returns fake profiling timestamps: 0/1/2/3 ns for consecutive
    // events (seen with clinfo and our own timer test). Time launches with host clocks there.
    bool fake_event_timestamps = false;
    // NVIDIA's clFinish / blocking reads spin a CPU core at 100 % while waiting. Prefer event
    // callbacks and user events in multi-device loops so the host thread stays free.
    bool blocking_wait_spins = false;
    // Local memory we allow a kernel to use: the reported size minus a margin, since some drivers
    // reserve part of it for their own use (rusticl reports 32 KiB on llvmpipe, NVIDIA 48 KiB).
    std::size_t usable_local_memory = 16 * 1024;
    // OpenCL 1.2 has no non-uniform work-groups anywhere: global sizes are always padded to a
    // multiple of the work-group size and kernels guard with `if (i >= n) return;`.
};

Quirks quirks_for(const DeviceInfo& info);

}  // namespace clsph::cl_rt
