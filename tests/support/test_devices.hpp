// Shared by the device test suites: every available device, opened once per test process (so
// programs build once), and a random seed drawn fresh per run and printed so failures reproduce.
#pragma once
#include "cl/device.hpp"

#include <cstdint>
#include <string>
#include <random>
#include <vector>

namespace clsph::test {

// Devices named by $CLSPH_TEST_DEVICES (default "all"), opened with profiling off.
std::vector<cl_rt::Device*> devices();

// $CLSPH_TEST_SEED if set, else a fresh random seed; printed to stdout the first time.
std::uint64_t seed();

// A generator for one test case: seeded from seed() and the case's own salt, so test cases do not
// depend on each other's order.
std::mt19937_64 rng(std::uint64_t salt);

}  // namespace clsph::test

namespace clsph::test {
// The --devices spec of the first `count` test devices (fewer if there are fewer).
std::string device_spec(std::size_t count);

// The selection spec of the device long validation runs use: pocl's threaded CPU device when it
// is present (the fastest CPU device in CI), otherwise the default selection.
std::string validation_device_spec();
}  // namespace clsph::test
