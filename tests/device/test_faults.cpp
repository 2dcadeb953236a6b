// OpenCL failures through the public API: faults injected in the runtime layer (Seams::faults: the
// Nth launch, allocation, read or build on a device fails with the driver's error code) reach the
// host program as typed DeviceErrors naming the call, the device and, during a run, the step, on
// one device and on three; after a failure mid-run the last good state still holds every particle.
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"

#include <doctest/doctest.h>

#include <string>

using namespace clsph;

namespace {

Scene small_scene() { return test::dam_break_slice(0.1, 0.01, 3.0, x_min | x_max | z_min); }

Options with_fault(std::size_t devices, testing::Fault fault) {
    Options o;
    o.devices = test::device_spec(devices);
    o.balance = BalanceMode::fixed;  // every device keeps a slab (an idle device launches nothing)
    testing::Seams seams;
    seams.faults.push_back(fault);
    testing::set_seams(o, std::move(seams));
    return o;
}

// The label of the device at position `d` of the first `count` test devices.
std::string label_of(std::size_t count, std::size_t d) {
    const auto devs = test::devices();
    return devs[std::min(d, std::min(count, devs.size()) - 1)]->label();
}

}  // namespace

TEST_SUITE("faults") {
    TEST_CASE("a launch failing mid-run: a DeviceError naming the step, the kernel, the call and the device") {
        const std::size_t counts[] = {1, 3};
        for (const std::size_t count : counts) {
            const std::size_t last = std::min(count, test::devices().size()) - 1;
            CAPTURE(count);
            const Scene scene = small_scene();
            Simulation sim(scene, with_fault(count, {testing::FaultCall::enqueue, 400, last, 0}));
            const std::size_t particles = sim.info().particles;
            (void)sim.particles();  // the last good state: t = 0
            try {
                for (int i = 0; i < 200; ++i) sim.step();
                FAIL("the 400th launch never came");
            } catch (const DeviceError& e) {
                const std::string m = e.what();
                CAPTURE(m);
                CHECK(e.code() == -5);  // CL_OUT_OF_RESOURCES
                CHECK(e.call() == "clEnqueueNDRangeKernel");
                CHECK(e.device() == label_of(count, last));
                CHECK(m.rfind("step ", 0) == 0);
                CHECK(m.find("launching kernel '") != std::string::npos);
                CHECK(m.find(" on " + label_of(count, last) + ": clEnqueueNDRangeKernel failed with CL_OUT_OF_RESOURCES (-5)") !=
                      std::string::npos);
            }
            CHECK(sim.last_good().size() == particles);
        }
    }

    TEST_CASE("a download failing: a DeviceError naming the read and the device") {
        const Scene scene = small_scene();
        Simulation sim(scene, with_fault(1, {testing::FaultCall::read, 25, 0, 0}));
        try {
            for (int i = 0; i < 50; ++i) {
                sim.step();
                (void)sim.particles();
            }
            FAIL("the 25th read never came");
        } catch (const DeviceError& e) {
            CHECK(e.call() == "clEnqueueReadBuffer");
            CHECK(e.device() == label_of(1, 0));
            CHECK(std::string(e.what()).find("clEnqueueReadBuffer failed with CL_OUT_OF_RESOURCES (-5)") != std::string::npos);
        }
    }

    TEST_CASE("an allocation or a build failing during set-up: DeviceError, BuildError (a DeviceError)") {
        const Scene scene = small_scene();
        for (const std::size_t count : {std::size_t{1}, std::size_t{3}}) {
            const std::size_t last = std::min(count, test::devices().size()) - 1;
            CAPTURE(count);
            try {
                Simulation sim(scene, with_fault(count, {testing::FaultCall::allocation, 2, last, 0}));
                FAIL("the allocation did not fail");
            } catch (const DeviceError& e) {
                CHECK(e.code() == -4);  // CL_MEM_OBJECT_ALLOCATION_FAILURE
                CHECK(e.call() == "clCreateBuffer");
                CHECK(e.device() == label_of(count, last));
                CHECK(std::string(e.what()).rfind("allocating buffer '", 0) == 0);
            }
            try {
                Simulation sim(scene, with_fault(count, {testing::FaultCall::build, 1, last, 0}));
                FAIL("the build did not fail");
            } catch (const BuildError& e) {
                CHECK(e.code() == -6);  // CL_OUT_OF_HOST_MEMORY
                CHECK(e.call() == "clBuildProgram");
                CHECK(e.device() == label_of(count, last));
                CHECK(e.log().find("CL_OUT_OF_HOST_MEMORY") != std::string::npos);
            }
        }
    }

    TEST_CASE("a fault with an explicit code fails with that code") {
        const Scene scene = small_scene();
        try {
            Simulation sim(scene, with_fault(1, {testing::FaultCall::allocation, 1, 0, -59}));  // CL_INVALID_OPERATION
            FAIL("the allocation did not fail");
        } catch (const DeviceError& e) {
            CHECK(e.code() == -59);
            CHECK(std::string(e.what()).find("CL_INVALID_OPERATION (-59)") != std::string::npos);
        }
    }

    TEST_CASE("CLSPH_TEST_FAULT's grammar: CALL:N[:DEVICE]") {
        const auto f = testing::parse_fault("read:12:2", "X");
        CHECK(f.call == testing::FaultCall::read);
        CHECK(f.nth == 12);
        CHECK(f.device == 2);
        CHECK(testing::parse_fault("build:1", "X").device == 0);
        for (const char* bad : {"", "read", "read:", "read:0", "read:1:", "write:1", "read:1:2:3", "read:-1", "read:1e3"}) {
            CAPTURE(bad);
            CHECK_THROWS_AS(testing::parse_fault(bad, "X"), Error);
        }
    }
}

// The step ahead on several devices (docs/multi_device.md): three pocl pthread devices (the suite's
// environment), the cell tables kept, the copies between devices through the relay's thread and
// user events. A launch or a read failing there (the read may be a copy's, staged for the relay)
// must come back as the same DeviceError, not leave a device waiting for a copy that never comes.
TEST_SUITE("faults_ahead") {
    TEST_CASE("a launch or a read failing while steps run ahead on three devices: a DeviceError naming it, no device left waiting") {
        REQUIRE_MESSAGE(test::devices().size() >= 3, "needs three devices (POCL_DEVICES=\"pthread pthread pthread\")");
        Scene scene = small_scene();
        const double dp = scene.physics.dp;
        scene.domain.max[1] = 10 * dp;  // the period: three cells of a support and the buffer
        scene.walls.front().max[1] = 9 * dp;
        scene.fluids.front().max[1] = 9.5 * dp;
        scene.domain.split_axis = 0;
        scene.run.list_buffer = 0.1;
        const testing::Fault faults[] = {{testing::FaultCall::enqueue, 300, 2, 0}, {testing::FaultCall::read, 400, 0, 0}};
        for (const auto& fault : faults) {
            const bool launch = fault.call == testing::FaultCall::enqueue;
            CAPTURE(launch);
            Options o = with_fault(3, fault);
            o.synchronous = false;
            Simulation sim(scene, o);
            REQUIRE(sim.steps_ahead());
            const std::size_t particles = sim.info().particles;
            (void)sim.particles();  // the last good state: t = 0
            try {
                for (int f = 1; f < 400; ++f) {
                    sim.run_until(f * 0.001);
                    (void)sim.particles();
                }
                FAIL("the fault never came");
            } catch (const DeviceError& e) {
                const std::string m = e.what();
                CAPTURE(m);
                CHECK(e.code() == -5);  // CL_OUT_OF_RESOURCES
                CHECK(e.call() == (launch ? "clEnqueueNDRangeKernel" : "clEnqueueReadBuffer"));
                CHECK(e.device() == label_of(3, fault.device));
                CHECK(m.rfind("step ", 0) == 0);
            }
            CHECK(sim.info().step > 10);  // (well into the run: steps ahead were taken)
            CHECK(sim.last_good().size() == particles);
        }
    }
}
