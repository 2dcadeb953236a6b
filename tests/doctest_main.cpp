#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "support/skip.hpp"

// doctest's own main, but a run in which nothing failed and a case called test_skip::skip exits
// test_skip::kReturnCode (77), which CTest reports as skipped (support/skip.hpp).
int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int failed = context.run();
    if (context.shouldExit() || failed != 0) return failed;
    return test_skip::exit_code();
}
