// Skips that CTest sees: a test case that cannot run what it is for here (too few devices, a file
// absent) calls test_skip::skip(why) and returns; tests/doctest_main.cpp then makes the binary exit
// kReturnCode when nothing failed, and CTest (SKIP_RETURN_CODE, tests/CMakeLists.txt) reports the
// test as "Skipped" instead of "Passed". The rule (docs/testing.md, "Skipped tests"): skip() only
// when the part a case is named for did not run (the whole case, or its several-device half when
// its name promises several devices); a case skipped by design (doctest::skip(), an opt-in
// variable) does not call it, and neither does a case that ran what it is for under another form.
#pragma once
#include <doctest/doctest.h>

#include <iostream>
#include <string>
#include <vector>

namespace test_skip {

// The exit status CTest reads as "skipped" (the Automake convention).
inline constexpr int kReturnCode = 77;

// What did not run, in the order it was skipped.
inline std::vector<std::string>& skipped() {
    static std::vector<std::string> s;
    return s;
}

// Record that the running case could not run (part of) what it is for, and why; says so in the log.
inline void skip(const std::string& why) {
    MESSAGE("SKIPPED: " << why);
    skipped().push_back(why);
}

// After the run: kReturnCode if anything was skipped (listed on stdout), else 0.
inline int exit_code() {
    if (skipped().empty()) return 0;
    std::cout << "[clsph tests] " << skipped().size() << " skipped (exit " << kReturnCode << ", CTest: Skipped):\n";
    for (const auto& why : skipped()) std::cout << "  " << why << "\n";
    std::cout << std::flush;
    return kReturnCode;
}

}  // namespace test_skip
