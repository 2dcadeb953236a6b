#include "cl/program_cache.hpp"

#include "cl/errors.hpp"
#include "cl/faults.hpp"
#include "cl/kernel_sources.hpp"
#include "clsph/error.hpp"

#include <functional>

namespace clsph::cl_rt {

ProgramCache::ProgramCache(cl::Context context, cl::Device device, std::string device_label, FaultInjector* faults,
                           std::string salt)
    : context_(std::move(context)),
      device_(std::move(device)),
      label_(std::move(device_label)),
      salt_(std::move(salt)),
      faults_(faults) {}

cl::Program& ProgramCache::program(const std::string& file, const std::string& options) {
    const std::string source = kernel_source(file);
    const std::string full_options = "-cl-std=CL1.2 " + options + (salt_.empty() ? "" : " " + salt_);
    const std::string key = file + "|" + std::to_string(std::hash<std::string>{}(source)) + "|" + full_options;
    if (auto it = programs_.find(key); it != programs_.end()) return it->second;

    cl::Program prog = guarded("creating program from " + file, label_, [&] { return cl::Program(context_, source, false); });
    try {
        if (faults_) faults_->before(testing::FaultCall::build, "clBuildProgram");
        prog.build(std::vector<cl::Device>{device_}, full_options.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
        } catch (const cl::Error&) {
            log = "(the driver gave no build log)";
        }
        if (e.err() != CL_BUILD_PROGRAM_FAILURE && e.err() != CL_INVALID_BUILD_OPTIONS)
            log = error_name(e.err()) + "\n" + log;
        throw BuildError(file, full_options, label_, log, e.err());
    }
    return programs_.emplace(key, std::move(prog)).first->second;
}

cl::Kernel ProgramCache::kernel(const std::string& file, const std::string& name, const std::string& options) {
    cl::Program& prog = program(file, options);
    return guarded("creating kernel '" + name + "' from " + file, label_, [&] { return cl::Kernel(prog, name.c_str()); });
}

}  // namespace clsph::cl_rt
