// Fault injection for tests (clsph/testing.hpp, Seams::faults): each Device counts its launches,
// allocations, reads and builds, and the planned one fails as the driver would fail it, by
// throwing the cl::Error the bindings throw for that call. Everything above this layer (the
// wrappers that turn it into a DeviceError, the step, the CLI's exit path) runs as for a real fault.
#pragma once
#include "cl/cl.hpp"
#include "clsph/fault.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph::cl_rt {

class FaultInjector {
public:
    FaultInjector() = default;
    explicit FaultInjector(std::vector<testing::Fault> faults) : faults_(std::move(faults)) {}
    // Before each call of kind `call` (the OpenCL function `cl_name`): throws cl::Error when a
    // planned fault says this is the call that fails. Thread-safe (a device's host thread and the
    // main thread both call it).
    void before(testing::FaultCall call, const char* cl_name);

private:
    std::vector<testing::Fault> faults_;
    std::array<std::atomic<std::uint64_t>, 4> counts_{};
};

}  // namespace clsph::cl_rt
