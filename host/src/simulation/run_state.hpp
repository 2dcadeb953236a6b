// Where a run stands: the last step's figures, the next step's size and the last state known good.
// Every part of the Simulation reads it; the step runners and set-up write it.
#pragma once
#include "clsph/checkpoint.hpp"
#include "clsph/scene.hpp"
#include "clsph/simulation.hpp"
#include "device/physics.hpp"
#include "multi/slab_driver.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace clsph::simulation {

struct RunState {
    StepInfo info;
    double dt_next = 0.0;
    double last_good_time = 0.0;  // the time of the state last_good() holds
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

    // The figures of a synchronous step's outcome (or the first pass) on `driver`'s slabs.
    void take(const multi::StepOutcome& k, multi::SlabDriver& driver) {
        info.removed += k.removed;
        info.created += k.created;
        info.particles = driver.owned();
        info.fluid = k.kick.fluid;
        info.kinetic_energy = k.kick.kinetic_energy;
        info.max_speed = std::sqrt(k.kick.max_speed2);
        info.cells = driver.slabs().size() == 1 && driver.here(0) ? driver.slabs()[0].cells->cells() : 0;
    }
    void restore(const Checkpoint& c) {
        info.step = c.step;
        info.time = c.time;
        info.dt = c.dt;
        info.removed = c.removed;
        info.created = c.created;
        info.fluid = c.fluid;
        info.kinetic_energy = c.kinetic_energy;
        info.max_speed = c.max_speed;
        info.cells = c.cells;
        dt_next = c.dt_next;
        last_good_time = c.time;
    }
    void stamp_wall_time() {
        info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    }
};

// Monaghan's force and acoustic (CFL) limits: dt = cfl min(sqrt(h/|a|max), h/(c0 + |v|max)), and
// with laminar viscosity at most 0.125 h^2 / nu; or the scene's fixed step. kernels/step_clock.cl does the same in double on the device (the step ahead).
inline double next_dt(const Scene& scene, const SphParams& sp, const device::KickResult& k) {
    if (scene.run.fixed_dt > 0) return scene.run.fixed_dt;
    const double h = sp.h;
    const double amax = std::sqrt(k.max_accel2), vmax = std::sqrt(k.max_speed2);
    const double dt_force = amax > 0 ? std::sqrt(h / amax) : std::numeric_limits<double>::infinity();
    const double dt_sound = h / (sp.c0 + vmax);
    return std::min(scene.physics.cfl * std::min(dt_force, dt_sound), scene.physics.viscous_dt());
}

}  // namespace clsph::simulation
