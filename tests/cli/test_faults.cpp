// Real OpenCL failures, injected in the runtime layer (CLSPH_TEST_FAULT: the Nth launch, allocation,
// read or build on a device fails with the driver's error code), on one device and on every device
// there is: the exit status, the message, last_good.vtu and run.json are what docs/cli.md says.
// The faults go to clsph-faulty, the test build of the tool; the shipped clsph has no such hook.
#include "support.hpp"

#include <doctest/doctest.h>

#include <cstdlib>

using namespace cli_test;

namespace {

struct Faulted {
    int code = 0;
    std::string log;
};

Faulted run_with_fault(const std::string& fault, const std::string& devices, const std::string& out,
                       const std::vector<std::string>& more = {}) {
    ::setenv("CLSPH_TEST_FAULT", fault.c_str(), 1);
    Faulted r;
    // Frames every 0.0005 s, so frames were downloaded before the failure.
    r.code = run_faulty(args({{"run", scene}, tiny, {"--devices", devices, "--until", "0.01", "--every", "0.0005", "--out", out}, more}), r.log);
    ::unsetenv("CLSPH_TEST_FAULT");
    return r;
}

void check_mid_run_failure(const Faulted& r, const std::string& out, const std::string& call, const std::string& error) {
    INFO(r.log);
    CHECK(r.code == 3);
    CHECK(r.log.find("clsph: error: ") != std::string::npos);
    CHECK(r.log.find(call + " failed with " + error) != std::string::npos);
    CHECK(r.log.find("step ") != std::string::npos);
    CHECK(r.log.find("last good state is in " + out + "/last_good.vtu") != std::string::npos);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "failed");
    CHECK(j.at("exit_status") == 3);
    CHECK(j.at("message").get<std::string>().find(call + " failed with " + error) != std::string::npos);
    // Every particle is in the last good state (none lost to the failure), at a frame's time.
    CHECK(clsph::read_vtu(out + "/last_good.vtu").size() == tiny_count().total);
    CHECK(clsph::read_pvd(out + "/dam_break.pvd").size() >= 1);
}

}  // namespace

TEST_CASE("a kernel launch failing mid-run on one device: exit 3, kernel, device and step named") {
    const std::string out = work_dir("fault_enqueue_one");
    const auto r = run_with_fault("enqueue:200", "0", out);
    check_mid_run_failure(r, out, "clEnqueueNDRangeKernel", "CL_OUT_OF_RESOURCES (-5)");
    CHECK(r.log.find("clsph: error: step ") != std::string::npos);
    CHECK(r.log.find("launching kernel '") != std::string::npos);
    CHECK(r.log.find(" on #0 ") != std::string::npos);
}

TEST_CASE("a download failing mid-run on one device: exit 3, the frame and the step named") {
    const std::string out = work_dir("fault_read_one");
    const auto r = run_with_fault("read:30", "0", out);
    check_mid_run_failure(r, out, "clEnqueueReadBuffer", "CL_OUT_OF_RESOURCES (-5)");
    CHECK(r.log.find("reading a buffer on #0 ") != std::string::npos);
}

TEST_CASE("failures on the last of several devices: exit 3 and the failing device named, no hang") {
    const std::size_t n = devices_picked("all");
    REQUIRE(n >= 1);
    const std::string last = std::to_string(n - 1);
    // --balance off: every device keeps its slab (a balancer may leave the last one idle, and an
    // idle device launches and reads nothing).
    SUBCASE("a launch") {
        const std::string out = work_dir("fault_enqueue_all");
        const auto r = run_with_fault("enqueue:250:" + last, "all", out, {"--balance", "off"});
        check_mid_run_failure(r, out, "clEnqueueNDRangeKernel", "CL_OUT_OF_RESOURCES (-5)");
        CHECK(r.log.find("clsph: error: step ") != std::string::npos);
        CHECK(r.log.find("on #" + last + " ") != std::string::npos);
    }
    SUBCASE("a launch on the middle device, every device holding a slab (--balance off)") {
        // With neighbours on both sides, waiting for what the failed device will never send.
        const std::string middle = std::to_string(n / 2);
        const std::string out = work_dir("fault_enqueue_middle");
        const auto r = run_with_fault("enqueue:300:" + middle, "all", out, {"--balance", "off"});
        check_mid_run_failure(r, out, "clEnqueueNDRangeKernel", "CL_OUT_OF_RESOURCES (-5)");
        CHECK(r.log.find("on #" + middle + " ") != std::string::npos);
    }
    SUBCASE("a read") {
        const std::string out = work_dir("fault_read_all");
        const auto r = run_with_fault("read:40:" + last, "all", out, {"--balance", "off"});
        check_mid_run_failure(r, out, "clEnqueueReadBuffer", "CL_OUT_OF_RESOURCES (-5)");
        CHECK(r.log.find("on #" + last + " ") != std::string::npos);
    }
}

TEST_CASE("an allocation or a build failing during set-up: exit 3, named, no output directory") {
    const std::size_t n = devices_picked("all");
    REQUIRE(n >= 1);
    for (const char* devices_text : {"0", "all"}) {
        const std::string devices = devices_text;
        const std::string last = devices == "all" ? std::to_string(n - 1) : "0";
        CAPTURE(devices);
        {
            const std::string out = work_dir("fault_allocation");
            const auto r = run_with_fault("allocation:3:" + last, devices, out);
            INFO(r.log);
            CHECK(r.code == 3);
            CHECK(r.log.find("clsph: error: allocating buffer '") != std::string::npos);
            CHECK(r.log.find("clCreateBuffer failed with CL_MEM_OBJECT_ALLOCATION_FAILURE (-4)") != std::string::npos);
            CHECK(r.log.find("on #" + last + " ") != std::string::npos);
            CHECK_FALSE(fs::exists(out));
        }
        {
            const std::string out = work_dir("fault_build");
            const auto r = run_with_fault("build:2:" + last, devices, out);
            INFO(r.log);
            CHECK(r.code == 3);
            CHECK(r.log.find("clsph: error: kernel build failed: ") != std::string::npos);
            CHECK(r.log.find("CL_OUT_OF_HOST_MEMORY") != std::string::npos);
            CHECK(r.log.find("on #" + last + " ") != std::string::npos);
            CHECK_FALSE(fs::exists(out));
        }
    }
}

TEST_CASE("a malformed CLSPH_TEST_FAULT is an error, not ignored") {
    for (const char* bad : {"seven", "enqueue", "enqueue:0", "launch:3", "read:3:x", "read:-1"}) {
        CAPTURE(bad);
        const std::string out = work_dir("fault_bad");
        std::string log;
        ::setenv("CLSPH_TEST_FAULT", bad, 1);
        const int code = run_faulty(args({{"run", scene}, tiny, {"--steps", "2", "--out", out}}), log);
        ::unsetenv("CLSPH_TEST_FAULT");
        INFO(log);
        CHECK(code == 1);
        CHECK(log.find("clsph: error: CLSPH_TEST_FAULT: expected CALL:N") != std::string::npos);
        CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("the shipped clsph ignores CLSPH_TEST_FAULT; only the test build clsph-faulty reads it") {
    // The fault that fails a run in the test build above (exit 3), and one that does not parse.
    const std::string fault_out = work_dir("fault_faulty_build");
    const auto faulted = run_with_fault("enqueue:200", "0", fault_out);
    INFO(faulted.log);
    REQUIRE(faulted.code == 3);
    for (const char* fault : {"enqueue:200", "seven"}) {
        CAPTURE(fault);
        const std::string out = work_dir("fault_shipped");
        std::string log;
        ::setenv("CLSPH_TEST_FAULT", fault, 1);
        const int code = run(args({{"run", scene}, tiny, {"--devices", "0", "--until", "0.01", "--every", "0.0005", "--out", out}}), log);
        ::unsetenv("CLSPH_TEST_FAULT");
        INFO(log);
        CHECK(code == 0);
        CHECK(log.find("CLSPH_TEST_FAULT") == std::string::npos);
        CHECK(read_json(out + "/run.json").at("status") == "completed");
    }
}
