#include "simulation/failures.hpp"

#include "shared.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace clsph::simulation {

void Failures::bad_particle(const multi::StepOutcome& k) const {
    const auto& info = state_.info;
    if (!driver_.here(k.bad_slab))
        throw SimulationError("step " + std::to_string(info.step + 1) + ": a particle of slab " + std::to_string(k.bad_slab) +
                              ", on another MPI rank, went bad (that rank's message names it). The run stopped; the last "
                              "good state is at t = " + std::to_string(state_.last_good_time) + " s.");
    auto& slab = driver_.slabs()[k.bad_slab];
    auto& d = *slab.device;
    const auto index = static_cast<std::size_t>(k.kick.bad_index);
    cl_uint id = 0;
    float vr[4] = {0, 0, 0, 0};
    d.read(slab.store->id, &id, 1, index);
    d.read(slab.store->velrho, vr, 4, 4 * index);
    bad_particle(id, vr, state_.dt_next, driver_.slabs().size() > 1 ? d.label() : std::string());
}

void Failures::bad_particle(std::uint32_t id, const float vr[4], double dt, const std::string& device) const {
    const auto& info = state_.info;
    std::ostringstream o;
    const bool fluid = (id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;
    o << "step " << info.step + 1 << ", t = " << info.time + dt << " s: particle " << (id & CLSPH_ID_MASK) << " ("
      << (fluid ? "fluid" : "boundary") << ") ";
    if (!std::isfinite(vr[0]) || !std::isfinite(vr[1]) || !std::isfinite(vr[2]) || !std::isfinite(vr[3]))
        o << "has a non-finite velocity or density";
    else
        o << "has density " << vr[3] << " kg/m^3, outside the allowed band [" << driver_.params().rho_min << ", "
          << driver_.params().rho_max << "]";
    if (!device.empty()) o << " on device " << device;
    o << " (time step " << dt << " s). The run stopped; the last good state is at t = " << state_.last_good_time << " s.";
    throw SimulationError(o.str());
}

void Failures::check_dt_collapse() const {
    if (scene_.run.fixed_dt > 0) return;
    const auto& sp = driver_.params();
    // With laminar viscosity the largest step may be the viscous limit, not the acoustic one.
    const double acoustic = std::min(scene_.physics.cfl * static_cast<double>(sp.h) / static_cast<double>(sp.c0),
                                     scene_.physics.viscous_dt());
    if (state_.dt_next >= options_.dt_collapse * acoustic) return;
    const auto& info = state_.info;
    std::ostringstream o;
    o << "step " << info.step << ", t = " << info.time << " s: the time step collapsed to " << state_.dt_next
      << " s (below " << options_.dt_collapse << " of the acoustic step " << acoustic << " s; max |v| = " << info.max_speed
      << " m/s): the accelerations blew up. The run stopped; the last good state is at t = " << state_.last_good_time
      << " s.";
    throw SimulationError(o.str());
}

void Failures::device_failed(const DeviceError& e, double dt) const {
    std::ostringstream o;
    o << "step " << state_.info.step + 1 << ", t = " << state_.info.time + dt << " s: " << e.what()
      << ". The run stopped; the last good state is at t = " << state_.last_good_time << " s.";
    throw DeviceError(e.code(), o.str(), e.call(), e.device());
}

}  // namespace clsph::simulation
