// How a run stops when it goes wrong: a particle gone bad (non-finite, or its density out of the
// band), a time step that collapsed, a device that failed mid-step. Each is the exception a user
// reads, naming the step, the time, the particle or device, and the last good state.
#pragma once
#include "clsph/error.hpp"
#include "clsph/options.hpp"
#include "clsph/scene.hpp"
#include "multi/slab_driver.hpp"
#include "simulation/run_state.hpp"

#include <cstdint>
#include <string>

namespace clsph::simulation {

class Failures {
public:
    Failures(const Scene& scene, const Options& options, multi::SlabDriver& driver, const RunState& state)
        : scene_(scene), options_(options), driver_(driver), state_(state) {}
    // A synchronous step's bad particle (k.kick.bad_index), read from its device now.
    [[noreturn]] void bad_particle(const multi::StepOutcome& k) const;
    // `id` the id word, `vr` velocity and density of the particle that failed in the step after
    // the state's (whose dt was `dt`); `device` empty on one device.
    [[noreturn]] void bad_particle(std::uint32_t id, const float vr[4], double dt, const std::string& device) const;
    // A CFL step below Options::dt_collapse of the acoustic step at rest stops the run with the
    // error a blow-up gives. Event clamps do not count: only the CFL step (dt_next) is checked.
    void check_dt_collapse() const;
    // A device failed mid-step: its state is lost, the last good state is on the host.
    [[noreturn]] void device_failed(const DeviceError& e, double dt) const;

private:
    const Scene& scene_;
    const Options& options_;
    multi::SlabDriver& driver_;
    const RunState& state_;
};

}  // namespace clsph::simulation
