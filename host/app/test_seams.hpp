// Test seams in the tool. The app's sources are built once and linked twice: the shipped `clsph`
// with no_test_seams.cpp, whose add_test_seams does nothing (so it never reads CLSPH_TEST_FAULT),
// and the test-only `clsph-faulty` (built with CLSPH_BUILD_TESTS, never installed) with
// test_seams.cpp, whose add_test_seams reads it. Tests that inject failures run clsph-faulty.
#pragma once
#include <clsph/options.hpp>

namespace clsph::app {

// Adds the test build's seams to a run's options; throws clsph::Error for a malformed setting.
void add_test_seams(Options& options);

}  // namespace clsph::app
