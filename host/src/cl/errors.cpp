#include "cl/errors.hpp"

namespace clsph {

BuildError::BuildError(std::string file, std::string options, std::string device, std::string log, int code)
    : DeviceError(code,
                  "kernel build failed: " + file + " on " + device + " with options '" + options +
                      "'\n--- build log ---\n" + log + "\n--- end of build log ---",
                  "clBuildProgram", device),
      file_(std::move(file)),
      options_(std::move(options)),
      log_(std::move(log)) {}

namespace cl_rt {

std::string error_name(cl_int code) {
    switch (code) {
#define CLSPH_ERR(name) \
    case name:          \
        return #name;
        CLSPH_ERR(CL_SUCCESS)
        CLSPH_ERR(CL_DEVICE_NOT_FOUND)
        CLSPH_ERR(CL_DEVICE_NOT_AVAILABLE)
        CLSPH_ERR(CL_COMPILER_NOT_AVAILABLE)
        CLSPH_ERR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        CLSPH_ERR(CL_OUT_OF_RESOURCES)
        CLSPH_ERR(CL_OUT_OF_HOST_MEMORY)
        CLSPH_ERR(CL_PROFILING_INFO_NOT_AVAILABLE)
        CLSPH_ERR(CL_MEM_COPY_OVERLAP)
        CLSPH_ERR(CL_IMAGE_FORMAT_MISMATCH)
        CLSPH_ERR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        CLSPH_ERR(CL_BUILD_PROGRAM_FAILURE)
        CLSPH_ERR(CL_MAP_FAILURE)
        CLSPH_ERR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        CLSPH_ERR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        CLSPH_ERR(CL_COMPILE_PROGRAM_FAILURE)
        CLSPH_ERR(CL_LINKER_NOT_AVAILABLE)
        CLSPH_ERR(CL_LINK_PROGRAM_FAILURE)
        CLSPH_ERR(CL_DEVICE_PARTITION_FAILED)
        CLSPH_ERR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        CLSPH_ERR(CL_INVALID_VALUE)
        CLSPH_ERR(CL_INVALID_DEVICE_TYPE)
        CLSPH_ERR(CL_INVALID_PLATFORM)
        CLSPH_ERR(CL_INVALID_DEVICE)
        CLSPH_ERR(CL_INVALID_CONTEXT)
        CLSPH_ERR(CL_INVALID_QUEUE_PROPERTIES)
        CLSPH_ERR(CL_INVALID_COMMAND_QUEUE)
        CLSPH_ERR(CL_INVALID_HOST_PTR)
        CLSPH_ERR(CL_INVALID_MEM_OBJECT)
        CLSPH_ERR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        CLSPH_ERR(CL_INVALID_IMAGE_SIZE)
        CLSPH_ERR(CL_INVALID_SAMPLER)
        CLSPH_ERR(CL_INVALID_BINARY)
        CLSPH_ERR(CL_INVALID_BUILD_OPTIONS)
        CLSPH_ERR(CL_INVALID_PROGRAM)
        CLSPH_ERR(CL_INVALID_PROGRAM_EXECUTABLE)
        CLSPH_ERR(CL_INVALID_KERNEL_NAME)
        CLSPH_ERR(CL_INVALID_KERNEL_DEFINITION)
        CLSPH_ERR(CL_INVALID_KERNEL)
        CLSPH_ERR(CL_INVALID_ARG_INDEX)
        CLSPH_ERR(CL_INVALID_ARG_VALUE)
        CLSPH_ERR(CL_INVALID_ARG_SIZE)
        CLSPH_ERR(CL_INVALID_KERNEL_ARGS)
        CLSPH_ERR(CL_INVALID_WORK_DIMENSION)
        CLSPH_ERR(CL_INVALID_WORK_GROUP_SIZE)
        CLSPH_ERR(CL_INVALID_WORK_ITEM_SIZE)
        CLSPH_ERR(CL_INVALID_GLOBAL_OFFSET)
        CLSPH_ERR(CL_INVALID_EVENT_WAIT_LIST)
        CLSPH_ERR(CL_INVALID_EVENT)
        CLSPH_ERR(CL_INVALID_OPERATION)
        CLSPH_ERR(CL_INVALID_GL_OBJECT)
        CLSPH_ERR(CL_INVALID_BUFFER_SIZE)
        CLSPH_ERR(CL_INVALID_MIP_LEVEL)
        CLSPH_ERR(CL_INVALID_GLOBAL_WORK_SIZE)
        CLSPH_ERR(CL_INVALID_PROPERTY)
        CLSPH_ERR(CL_INVALID_IMAGE_DESCRIPTOR)
        CLSPH_ERR(CL_INVALID_COMPILER_OPTIONS)
        CLSPH_ERR(CL_INVALID_LINKER_OPTIONS)
        CLSPH_ERR(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef CLSPH_ERR
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "unknown OpenCL error " + std::to_string(code);
    }
}

void check(cl_int code, const std::string& what, const std::string& device) {
    if (code == CL_SUCCESS) return;
    std::string msg = what;
    if (!device.empty()) msg += " on " + device;
    msg += ": " + error_name(code) + " (" + std::to_string(code) + ")";
    throw DeviceError(code, msg, {}, device);
}

DeviceError device_error(const cl::Error& e, const std::string& what, const std::string& device) {
    std::string msg = what;
    if (!device.empty()) msg += " on " + device;
    msg += ": " + std::string(e.what()) + " failed with " + error_name(e.err()) + " (" + std::to_string(e.err()) + ")";
    return DeviceError(e.err(), msg, e.what(), device);
}

}  // namespace cl_rt
}  // namespace clsph
