// OpenCL error codes by name, and the conversion of failures into clsph's typed errors.
#pragma once
#include "cl/cl.hpp"
#include "clsph/error.hpp"
#include <string>

namespace clsph::cl_rt {

// "CL_OUT_OF_RESOURCES" for -5; "unknown OpenCL error -1234" for codes we do not know.
std::string error_name(cl_int code);

// Throws DeviceError("<what> on <device>: CL_NAME (code)") when code != CL_SUCCESS.
void check(cl_int code, const std::string& what, const std::string& device = {});

// The DeviceError for a cl::Error the bindings threw: "<what> on <device>: <call> failed with
// CL_NAME (code)".
DeviceError device_error(const cl::Error& e, const std::string& what, const std::string& device);

// Runs f(); a cl::Error it throws becomes a DeviceError naming the call, the device and the error.
template <class F>
decltype(auto) guarded(const std::string& what, const std::string& device, F&& f) {
    try {
        return f();
    } catch (const cl::Error& e) {
        throw device_error(e, what, device);
    }
}

}  // namespace clsph::cl_rt
