// The options of the whole-run suites (validation, mdbc, symplectic): one device, the one
// validation_device_spec() names (pocl's threaded CPU device in CI).
#pragma once
#include "clsph/simulation.hpp"
#include "support/test_devices.hpp"

namespace clsph::test {

inline Options validation_options() {
    Options o;
    o.devices = validation_device_spec();
    return o;
}

}  // namespace clsph::test
