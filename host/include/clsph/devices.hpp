// Which OpenCL devices exist and which ones a run uses. No OpenCL types here: a host program can
// list and select devices without including OpenCL headers.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph {

struct DeviceInfo {
    std::size_t index = 0;          // stable: platforms sorted by name, devices in platform order
    std::string platform;           // platform name, e.g. "Portable Computing Language"
    std::string vendor;             // platform vendor
    std::string name;               // device name
    std::string type;               // "gpu", "cpu", "accelerator" or "other"
    std::string driver_version;
    std::string opencl_c_version;   // e.g. "OpenCL C 1.2 "
    std::uint32_t compute_units = 0;
    std::uint64_t global_memory = 0;  // bytes
    std::uint64_t max_allocation = 0; // bytes
    std::uint64_t local_memory = 0;   // bytes
    std::size_t max_work_group_size = 0;
    bool fp64 = false;                // cl_khr_fp64: the step ahead's clock (docs/multi_device.md)
    bool is_gpu() const { return type == "gpu"; }
    bool is_cpu() const { return type == "cpu"; }
};

// Every device of every platform that has devices (empty platforms are skipped), in the stable order.
// Throws DeviceSelectionError when there is no OpenCL platform at all (with how to install pocl).
std::vector<DeviceInfo> list_devices();

// The selection grammar shared by --devices and CLSPH_DEVICES:
//   "all" | "gpu" | "cpu" | "default" | indices "0,2" | "platform:TEXT" (name or vendor, any case)
// and comma-separated combinations of these. "default" (and an empty spec): every GPU if there is
// one, otherwise every CPU device, otherwise everything. Returns indices into `devices`, sorted and
// unique; throws DeviceSelectionError listing what exists when nothing matches or a term is bad.
std::vector<std::size_t> select_devices(const std::vector<DeviceInfo>& devices, const std::string& spec);

// The spec to use when the caller gives none: $CLSPH_DEVICES if set, else "default".
std::string default_device_spec();

// A table of devices (what `clsph devices` prints).
std::string format_device_table(const std::vector<DeviceInfo>& devices);

}  // namespace clsph
