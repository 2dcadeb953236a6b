# Skips that CTest sees (docs/testing.md, "Skipped tests"): a run in which nothing failed and a test
# was skipped (pytest.skip, skipif: something it needs is absent here) exits 77, which the `python`
# test's SKIP_RETURN_CODE (python/CMakeLists.txt) reports as skipped instead of passed. The same
# rule as the C++ suites (tests/support/skip.hpp): skip only what could not run, never by design.

SKIP_RETURN_CODE = 77


def pytest_sessionfinish(session, exitstatus):
    if exitstatus != 0:
        return
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None and reporter.stats.get("skipped"):
        session.exitstatus = SKIP_RETURN_CODE
