// Injected OpenCL failures, for tests (clsph/testing.hpp, Seams::faults). Kept apart from
// testing.hpp so the runtime layer can name them without the Simulation API.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace clsph::testing {

// The OpenCL calls a Fault can make fail, counted per device from the start of the Simulation.
enum class FaultCall {
    enqueue,     // a kernel launch (clEnqueueNDRangeKernel)
    allocation,  // a device buffer (clCreateBuffer), pinned host memory included
    read,        // a download (clEnqueueReadBuffer), blocking or not
    build,       // a program build (clBuildProgram)
};
// "enqueue", "allocation", "read", "build"; throws clsph::Error for anything else.
FaultCall fault_call_from_name(const std::string& name);
const char* fault_call_name(FaultCall call);

// The `nth` call of kind `call` on device `device` (its position in the selection) fails as the
// driver would fail it, with `code` (a cl_int; 0: the usual code for that call, e.g.
// CL_OUT_OF_RESOURCES for a launch). The fault is injected in the OpenCL runtime layer, below
// every wrapper, so what a test sees is what a real failure of that call produces.
struct Fault {
    FaultCall call = FaultCall::enqueue;
    std::uint64_t nth = 1;
    std::size_t device = 0;
    int code = 0;
};
// "CALL:N[:DEVICE]" (as CLSPH_TEST_FAULT takes it) to a Fault; throws clsph::Error naming `what`.
Fault parse_fault(const std::string& text, const std::string& what);

}  // namespace clsph::testing
