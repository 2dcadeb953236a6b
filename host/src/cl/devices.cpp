// Device enumeration (OpenCL) and the selection grammar (pure string/list logic).
#include "clsph/devices.hpp"

#include "cl/cl.hpp"
#include "cl/errors.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace clsph {
namespace {

std::string lower(std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(const std::string& s) {
    // Some drivers include the terminating NUL in string queries; drop it with the blanks.
    const char* blank = " \t\n\r";
    const auto b = s.find_first_not_of(std::string(blank) + '\0');
    if (b == std::string::npos) return {};
    const auto e = s.find_last_not_of(std::string(blank) + '\0');
    return s.substr(b, e - b + 1);
}

std::string type_name(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "gpu";
    if (t & CL_DEVICE_TYPE_CPU) return "cpu";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

std::string what_exists(const std::vector<DeviceInfo>& devices) {
    if (devices.empty()) return "no OpenCL devices exist";
    std::string s = "devices that exist:\n";
    for (const auto& d : devices)
        s += "  " + std::to_string(d.index) + ": " + d.name + " (" + d.type + ", " + d.platform + ")\n";
    return s;
}

}  // namespace

namespace cl_rt {
// The devices of a platform, empty when it has none. (The C++ bindings throw on
// CL_DEVICE_NOT_FOUND, which an empty platform such as Mesa's Clover without GPUs returns.)
std::vector<cl::Device> platform_devices(const cl::Platform& platform) {
    cl_uint count = 0;
    if (clGetDeviceIDs(platform(), CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS || count == 0) return {};
    std::vector<cl_device_id> ids(count);
    if (clGetDeviceIDs(platform(), CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr) != CL_SUCCESS) return {};
    std::vector<cl::Device> out;
    for (auto id : ids) out.emplace_back(id, false);
    return out;
}
}  // namespace cl_rt

namespace {

std::string mib(std::uint64_t bytes) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(0) << static_cast<double>(bytes) / (1024.0 * 1024.0) << " MiB";
    return o.str();
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
    std::vector<cl::Platform> platforms;
    cl_int err = cl::Platform::get(&platforms);
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || platforms.empty()) {
        throw DeviceSelectionError(
            "no OpenCL platform found: install an OpenCL driver, e.g. for CPUs "
            "`apt-get install pocl-opencl-icd` (or your GPU vendor's OpenCL ICD)");
    }
    cl_rt::check(err, "listing OpenCL platforms");

    struct Entry { std::string name; std::size_t order; cl::Platform platform; };
    std::vector<Entry> entries;
    for (std::size_t i = 0; i < platforms.size(); ++i)
        entries.push_back({platforms[i].getInfo<CL_PLATFORM_NAME>(), i, platforms[i]});
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.name < b.name; });

    std::vector<DeviceInfo> out;
    for (auto& e : entries) {
        // Platforms with no devices (Mesa's Clover on a machine without its GPUs) are skipped.
        const std::vector<cl::Device> devs = cl_rt::platform_devices(e.platform);
        if (devs.empty()) continue;
        const std::string vendor = e.platform.getInfo<CL_PLATFORM_VENDOR>();
        for (const auto& d : devs) {
            DeviceInfo info;
            info.index = out.size();
            info.platform = e.name;
            info.vendor = vendor;
            info.name = trim(d.getInfo<CL_DEVICE_NAME>());
            info.type = type_name(d.getInfo<CL_DEVICE_TYPE>());
            info.driver_version = trim(d.getInfo<CL_DRIVER_VERSION>());
            info.opencl_c_version = trim(d.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
            info.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
            info.global_memory = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            info.max_allocation = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
            info.local_memory = d.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
            info.max_work_group_size = d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
            info.fp64 = d.getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_fp64") != std::string::npos;  // as physics.cpp decides
            out.push_back(std::move(info));
        }
    }
    if (out.empty())
        throw DeviceSelectionError(
            "OpenCL platforms exist but none has a device: install a driver with devices, e.g. "
            "`apt-get install pocl-opencl-icd` for CPUs");
    return out;
}

std::vector<std::size_t> select_devices(const std::vector<DeviceInfo>& devices, const std::string& spec_in) {
    std::string spec = trim(spec_in);
    if (spec.empty()) spec = "default";
    std::vector<std::size_t> chosen;
    std::stringstream ss(spec);
    std::string term;
    while (std::getline(ss, term, ',')) {
        term = trim(term);
        const std::string t = lower(term);
        if (t.empty()) throw DeviceSelectionError("device selection '" + spec + "': empty term\n" + what_exists(devices));
        std::vector<std::size_t> match;
        if (t == "all") {
            for (const auto& d : devices) match.push_back(d.index);
        } else if (t == "gpu" || t == "cpu") {
            for (const auto& d : devices)
                if (d.type == t) match.push_back(d.index);
        } else if (t == "default") {
            for (const auto& d : devices)
                if (d.is_gpu()) match.push_back(d.index);
            if (match.empty())
                for (const auto& d : devices)
                    if (d.is_cpu()) match.push_back(d.index);
            if (match.empty())
                for (const auto& d : devices) match.push_back(d.index);
        } else if (t.rfind("platform:", 0) == 0) {
            const std::string want = t.substr(9);
            if (want.empty())
                throw DeviceSelectionError("device selection '" + spec + "': 'platform:' needs a name\n" + what_exists(devices));
            for (const auto& d : devices)
                if (lower(d.platform).find(want) != std::string::npos || lower(d.vendor).find(want) != std::string::npos)
                    match.push_back(d.index);
        } else if (std::all_of(t.begin(), t.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
            const unsigned long long i = std::strtoull(t.c_str(), nullptr, 10);
            if (t.size() > 6 || i >= devices.size())
                throw DeviceSelectionError("device selection '" + spec + "': there is no device " + term + " (" +
                                           std::to_string(devices.size()) + " exist)\n" + what_exists(devices));
            match.push_back(static_cast<std::size_t>(i));
        } else {
            throw DeviceSelectionError("device selection '" + spec + "': unknown term '" + term +
                                       "' (use all, gpu, cpu, default, indices like 0,2, or platform:NAME)\n" +
                                       what_exists(devices));
        }
        if (match.empty())
            throw DeviceSelectionError("device selection '" + spec + "': '" + term + "' matches no device\n" +
                                       what_exists(devices));
        chosen.insert(chosen.end(), match.begin(), match.end());
    }
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    return chosen;
}

std::string default_device_spec() {
    const char* env = std::getenv("CLSPH_DEVICES");
    return (env && *env) ? std::string(env) : std::string("default");
}

std::string format_device_table(const std::vector<DeviceInfo>& devices) {
    std::ostringstream o;
    o << std::left << std::setw(4) << "#" << std::setw(30) << "platform" << std::setw(44) << "device" << std::setw(6)
      << "type" << std::right << std::setw(5) << "CUs" << std::setw(12) << "global" << std::setw(12) << "max alloc"
      << std::setw(10) << "local" << "  OpenCL C\n";
    for (const auto& d : devices) {
        auto cut = [](const std::string& s, std::size_t n) { return s.size() < n ? s : s.substr(0, n - 2) + "~"; };
        o << std::left << std::setw(4) << d.index << std::setw(30) << cut(d.platform, 30) << std::setw(44)
          << cut(d.name, 44) << std::setw(6) << d.type << std::right << std::setw(5) << d.compute_units << std::setw(12)
          << mib(d.global_memory) << std::setw(12) << mib(d.max_allocation) << std::setw(7)
          << d.local_memory / 1024 << " KiB" << "  " << d.opencl_c_version << "\n";
    }
    return o.str();
}

}  // namespace clsph
