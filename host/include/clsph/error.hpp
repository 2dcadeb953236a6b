// Typed errors: every message says what went wrong in the user's terms (file and key, device,
// OpenCL error name, kernel build log), so a host program can catch clsph::Error and print what().
#pragma once
#include <stdexcept>
#include <string>

namespace clsph {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// No OpenCL platform/device, or a device selection that matches nothing.
class DeviceSelectionError : public Error {
public:
    using Error::Error;
};

// An OpenCL call failed (whether the bindings threw or returned the code): code() is the raw
// cl_int; the message names what clsph was doing (the kernel, the buffer), the device, the OpenCL
// call and the error by name ("launching kernel 'sph.forces' on #1 pthread-... (Portable
// Computing Language): clEnqueueNDRangeKernel failed with CL_OUT_OF_RESOURCES (-5)"), and, during
// a run, the step. call() and device() are those parts alone (empty where not known).
class DeviceError : public Error {
public:
    DeviceError(int code, const std::string& message, std::string call = {}, std::string device = {})
        : Error(message), code_(code), call_(std::move(call)), device_(std::move(device)) {}
    int code() const noexcept { return code_; }
    const std::string& call() const noexcept { return call_; }
    const std::string& device() const noexcept { return device_; }

private:
    int code_;
    std::string call_, device_;
};

// A kernel failed to compile: the message holds the file, the options, the device and the full
// log. A DeviceError (code() is the cl_int clBuildProgram returned), as it is the driver that fails.
class BuildError : public DeviceError {
public:
    BuildError(std::string file, std::string options, std::string device, std::string log, int code = -11);
    const std::string& file() const noexcept { return file_; }
    const std::string& options() const noexcept { return options_; }
    const std::string& log() const noexcept { return log_; }

private:
    std::string file_, options_, log_;
};

// A device allocation that would not fit: needed vs available, checked before the driver is asked.
class OutOfDeviceMemory : public Error {
public:
    using Error::Error;
};

// A scene (file or built in code) that is malformed or physically impossible; names file and key.
class SceneError : public Error {
public:
    using Error::Error;
};

// The simulation itself failed (non-finite values, density out of band): names step, time, particle.
class SimulationError : public Error {
public:
    using Error::Error;
};

// Across MPI ranks (clsph/ranks.hpp): another rank gave up the step (a device of its failed, say),
// so this rank gave up its own rather than wait for that rank's messages. rank() is the rank that
// gave up first; the message is "rank R of N: " and that rank's error. After it (or a DeviceError
// given up), every rank calls recover() (clsph/ranks.hpp) before the ranks run anything together.
class RankFailure : public Error {
public:
    RankFailure(int rank, const std::string& message) : Error(message), rank_(rank) {}
    int rank() const noexcept { return rank_; }

private:
    int rank_;
};

}  // namespace clsph
