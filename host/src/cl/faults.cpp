#include "cl/faults.hpp"

#include "clsph/error.hpp"

#include <vector>

namespace clsph {
namespace testing {

FaultCall fault_call_from_name(const std::string& name) {
    if (name == "enqueue") return FaultCall::enqueue;
    if (name == "allocation") return FaultCall::allocation;
    if (name == "read") return FaultCall::read;
    if (name == "build") return FaultCall::build;
    throw Error("unknown OpenCL call '" + name + "' (use enqueue, allocation, read or build)");
}

const char* fault_call_name(FaultCall call) {
    switch (call) {
        case FaultCall::enqueue: return "enqueue";
        case FaultCall::allocation: return "allocation";
        case FaultCall::read: return "read";
        case FaultCall::build: return "build";
    }
    return "?";
}

Fault parse_fault(const std::string& text, const std::string& what) {
    const std::string usage = what + ": expected CALL:N or CALL:N:DEVICE (CALL enqueue, allocation, read or build; N >= 1), got '" + text + "'";
    std::vector<std::string> parts;
    for (std::size_t from = 0;;) {  // every part, empty ones included ("read:1:" has three)
        const std::size_t colon = text.find(':', from);
        parts.push_back(text.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
        if (colon == std::string::npos) break;
        from = colon + 1;
    }
    if (parts.size() < 2 || parts.size() > 3) throw Error(usage);
    auto whole = [&](const std::string& s) {
        if (s.empty() || s.size() > 12 || s.find_first_not_of("0123456789") != std::string::npos) throw Error(usage);
        return std::stoull(s);
    };
    Fault f;
    try {
        f.call = fault_call_from_name(parts[0]);
    } catch (const Error&) {
        throw Error(usage);
    }
    f.nth = whole(parts[1]);
    if (f.nth == 0) throw Error(usage);
    if (parts.size() == 3) f.device = static_cast<std::size_t>(whole(parts[2]));
    return f;
}

}  // namespace testing

namespace cl_rt {
namespace {

cl_int usual_code(testing::FaultCall call) {
    switch (call) {
        case testing::FaultCall::enqueue: return CL_OUT_OF_RESOURCES;
        case testing::FaultCall::allocation: return CL_MEM_OBJECT_ALLOCATION_FAILURE;
        case testing::FaultCall::read: return CL_OUT_OF_RESOURCES;
        case testing::FaultCall::build: return CL_OUT_OF_HOST_MEMORY;
    }
    return CL_OUT_OF_RESOURCES;
}

}  // namespace

void FaultInjector::before(testing::FaultCall call, const char* cl_name) {
    if (faults_.empty()) return;
    const std::uint64_t n = ++counts_[static_cast<std::size_t>(call)];
    for (const auto& f : faults_)
        if (f.call == call && f.nth == n) throw cl::Error(f.code != 0 ? f.code : usual_code(call), cl_name);
}

}  // namespace cl_rt
}  // namespace clsph
