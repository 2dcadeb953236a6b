// Seams for tests and benchmarks, not for applications: they make a run misbehave on purpose (a
// slow device, a device that fails, cuts forced from outside) so the code that copes with it can
// be checked. Set them on Options through clsph::testing::set_seams. Not installed: host/testing/
// is on the include path of the library and of the clsph_testing target (tests, benchmarks).
#pragma once
#include "clsph/fault.hpp"
#include "clsph/options.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace clsph::testing {

struct Seams {
    // Repeat device d's force pass slowdown[d] times (a device k times slower; the calibration
    // before the first step does not see it, as a device that becomes slow mid-run).
    std::vector<int> slowdown;
    // Run each device's force pass alone (wait for it before starting the next), so devices that
    // share a CPU are timed without each other's load. The pass is then never split around the
    // halo (the interiors' passes would run together).
    bool serialize_devices = false;
    // OpenCL calls that fail (see Fault).
    std::vector<Fault> faults;
    // Every exchange sends from whole slabs and merges with one sort, the path a particle that
    // jumped more than a column takes (the CFL limit rules that out, so tests force it here).
    bool wide_exchange = false;
    // Every device's CL_DEVICE_MAX_MEM_ALLOC_SIZE as if its driver reported this (0: as reported):
    // the memory plan splits devices into slabs by it and the memory tracker refuses larger buffers.
    std::uint64_t max_allocation = 0;
    // Every device opened as at least this many slabs (0 or 1: as the memory plan decides): what
    // several slabs cost, measured on one device (bench/bench_sph.cpp --slabs).
    std::size_t slabs = 0;
    // Every device runs the step's launches as they were before fusion (issue 30: a launch per
    // stage, the scans' tile sums scanned on their own): for the tests that the fused step is
    // bitwise the same.
    bool unfused = false;
    // Every force pass waits for the arrivals, as before the halo was overlapped with the interior
    // (docs/multi_device.md): for the tests that both give the same bits, and for measuring it.
    bool whole_force_pass = false;
    // Cuts to force before each step (devices + 1 column indices), instead of the balancer's.
    std::function<std::vector<std::size_t>(std::uint64_t step, std::size_t columns)> cut_schedule;
};

inline void set_seams(Options& options, Seams seams) { options.seams = std::make_shared<const Seams>(std::move(seams)); }

}  // namespace clsph::testing
