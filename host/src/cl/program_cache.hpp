// Programs built per device with explicit options and cached by (source hash, options).
#pragma once
#include "cl/cl.hpp"

#include <map>
#include <string>

namespace clsph::cl_rt {

class FaultInjector;

class ProgramCache {
public:
    // `salt`: options appended to every build on this device (Quirks::build_salt).
    ProgramCache(cl::Context context, cl::Device device, std::string device_label, FaultInjector* faults = nullptr,
                 std::string salt = {});
    // Builds kernels/<file> with "-cl-std=CL1.2 <options>" (once per distinct source+options) and
    // returns a fresh kernel object (kernels hold their arguments, so each user gets its own).
    // A build failure throws BuildError with the file, options, device and full build log.
    cl::Kernel kernel(const std::string& file, const std::string& name, const std::string& options = {});
    cl::Program& program(const std::string& file, const std::string& options = {});
    std::size_t size() const { return programs_.size(); }
    const std::string& salt() const { return salt_; }

private:
    cl::Context context_;
    cl::Device device_;
    std::string label_;
    std::string salt_;
    FaultInjector* faults_;
    std::map<std::string, cl::Program> programs_;
};

}  // namespace clsph::cl_rt
