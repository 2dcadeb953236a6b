// clsph-faulty, the test build of the tool (test_seams.hpp): CLSPH_TEST_FAULT=CALL:N[:DEVICE] makes
// the Nth OpenCL call of that kind (enqueue, allocation, read, build) on that device fail in the
// runtime layer, as a driver would fail it, so the whole error path runs as for a real failure
// (clsph/testing.hpp). The tests in tests/cli and tests/mpi that inject failures run this build.
#include "test_seams.hpp"

#include <clsph/testing.hpp>

#include <cstdlib>
#include <utility>

namespace clsph::app {

void add_test_seams(Options& options) {
    const char* v = std::getenv("CLSPH_TEST_FAULT");
    if (!v) return;
    testing::Seams seams;
    seams.faults.push_back(testing::parse_fault(v, "CLSPH_TEST_FAULT"));
    testing::set_seams(options, std::move(seams));
}

}  // namespace clsph::app
