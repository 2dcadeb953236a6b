// Driver facts that change how we drive a device, all in one place, each with its evidence.
#pragma once
#include "clsph/devices.hpp"
#include <cstddef>

namespace clsph::cl_rt {

struct Quirks {
    // Mesa rusticl 22.3 (Debian 12) returns fake profiling timestamps: 0/1/2/3 ns for consecutive
    // events (seen with clinfo and our own timer test). Time launches with host clocks there.
    bool fake_event_timestamps = false;
    // (NVIDIA's clFinish / blocking reads spin a CPU core at 100 % while waiting: the step waits
    // through cl/async.hpp's EventSet, on callbacks or by polling, never by a blocking wait.)
    // Local memory we allow a kernel to use: the reported size minus a margin, since some drivers
    // reserve part of it for their own use (rusticl reports 32 KiB on llvmpipe, NVIDIA 48 KiB).
    std::size_t usable_local_memory = 16 * 1024;
    // OpenCL 1.2 has no non-uniform work-groups anywhere: global sizes are always padded to a
    // multiple of the work-group size and kernels guard with `if (i >= n) return;`.

    // --- found while writing the primitives (sort, scan, compaction) ---
    // Mesa rusticl 22.3 reports CL_KERNEL_WORK_GROUP_SIZE = 32 for every kernel, whatever its
    // registers or local memory, yet runs larger work-groups correctly (kernels full of barriers,
    // checked against CPU results: the scan at 64, 256 and 1024 work-items, the device maximum;
    // the radix sort at 64 and 256). Where set, the per-kernel query is ignored and the device
    // limit used instead.
    bool kernel_work_group_size_understated = false;
    // (rusticl 22.3 also reports CL_KERNEL_LOCAL_MEM_SIZE as twice the kernel's local arrays and
    // does not enforce the limit; we budget local memory from the device's reported size.)
    // NVIDIA's OpenCL (driver 580.159.04, two H200s joined by NVLink): clEnqueueCopyBuffer in one
    // context holding both GPUs, from a buffer last written on the other GPU, took ~200 ms at every
    // size from 1 KiB to 256 MiB, where staging through pinned host memory across two contexts took
    // 36 us (1 KiB) to 9.8 ms (256 MiB) (clsph-bench-transfer; BENCHMARKS.md). So data moves
    // between devices by staging (multi/link.hpp), with one context per device, on every vendor.
    // NVIDIA's OpenCL (driver 580.159.04, H200): completion callbacks of transfer events (reads into
    // pinned host memory) arrive ~10 ms after the copy is done. On two H200s with 21 M particles the
    // exchange's read phase took 11.0 ms/step waiting on callbacks and 0.2 ms with clWaitForEvents
    // (36.95 vs 48.82 ms/step; BENCHMARKS.md). Where set, EventSet polls the events' status with
    // short sleeps instead (clWaitForEvents is on time too, but spins a core).
    bool late_transfer_callbacks = false;
    // pocl 3.1 (Debian 12): two pocl CPU devices of one kind in one process share each kernel's
    // compiled library, and running it on both at once breaks pocl's count of its users: the
    // process stops in pocl's own assertion (`pocl_release_dlhandle_cache: found->ref_count > 0`).
    // Two basic devices stop there within a few steps of the dam break, every time (the binary
    // before this change too); three pthread devices did once in a CI run's render test. A define
    // naming the device gives each pocl device its own binaries, so nothing is shared. Appended
    // to every kernel build on that device, with a second define for each further slab of it
    // (device.cpp): one pthread device opened as four slabs stopped there every time without.
    std::string build_salt;

    // --- found while speeding up the interaction pass (issue 12) ---
    // Build options for the interaction kernels only. NVIDIA (driver 580.159.04, H200): capping the
    // force kernel at 48 registers (-cl-nv-maxrregcount, an NVIDIA-only option) took SPHERIC-2's
    // force pass at dp 0.006 from 9.11 to 8.84 ms (32: 13.8, 40: 12.7, 64: 13.0, 96: 12.7 ms at
    // reach 1; clsph-bench-interaction, BENCHMARKS.md). Elsewhere empty: the portable path.
    const char* interaction_options = "";
    // Mesa rusticl 22.3 (llvmpipe) runs work-items in SIMD lanes itself, so the CPU form (a
    // work-item per cell, vector lanes inside it) gains nothing there: SPHERIC-2 at dp 0.02, force
    // pass 1417 ms for lanes against 1275 ms for fine (pocl pthread: lanes 34 ms, fine 1220 ms;
    // clsph-bench-interaction, BENCHMARKS.md). Where set, the automatic choice on a CPU is fine.
    bool vectorises_work_items = false;
    // Mesa rusticl 22.3 (llvmpipe): atomic_min on a __global uint wrote nothing in the renderer's
    // depth pass (0 of 72,011 pixels of a sphere; a plain min or an atomic_cmpxchg loop drew all of
    // them: tests/device/test_render.cpp). Where set, the depth pass uses the compare-and-swap loop.
    bool atomic_min_unreliable = false;

    // --- found while running steps ahead on several devices (issue 33) ---
    // pocl 3.1 (Debian 12), the basic device: completing a user event (clSetUserEventStatus) runs
    // the commands waiting for it on the calling thread, which then waits for a lock pocl holds
    // there: the process stops, the enqueueing thread waiting for the same lock (a basic and a
    // pthread device, the ghosts' copies of the step ahead: tests/device/test_step_ahead.cpp).
    // The pthread device does not. Where set, the step ahead on several devices, whose copies
    // across contexts complete user events (cl/relay.hpp), stays off (the synchronous step).
    bool user_events_stop = false;
};

Quirks quirks_for(const DeviceInfo& info);

}  // namespace clsph::cl_rt
