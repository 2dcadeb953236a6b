// What clsph::Simulation is made of: the scene and options it was given, the grid, and its parts,
// each owning its own state and doing one job (simulation/*.hpp):
//   setup       the devices opened after the memory plan, the slab driver and its first pass
//   RunState    where the run stands (the step's figures, the next dt, the last good time)
//   Failures    the errors a bad particle, a collapsed step or a failed device stop the run with
//   StepRunner  the synchronous step          StepAhead  steps run ahead of the host
//   Downloads   particles to the host, and the last good state
//   FrameCache  what images are drawn with on each device, kept from frame to frame
//   DeviceParts the free surface's buffers on each device, sized by capacities kept likewise
// The slab driver (multi/) owns the slabs and what a checkpoint saves of them; views (surface,
// image) and reports are stateless calls on it (simulation/views.cpp, reports.cpp).
#pragma once
#include "clsph/simulation.hpp"

#include "cl/errors.hpp"
#include "device/grid.hpp"
#include "device/memory_model.hpp"
#include "multi/slab_driver.hpp"
#include "render/frame_cache.hpp"
#include "surface/extract.hpp"
#include "simulation/downloads.hpp"
#include "simulation/failures.hpp"
#include "simulation/run_state.hpp"
#include "simulation/setup.hpp"
#include "simulation/step_ahead.hpp"
#include "simulation/step_runner.hpp"

#include <functional>

namespace clsph {


struct Simulation::Impl {
    Scene scene;
    Options options;
    device::Grid grid;
    simulation::Source source;  // its particles and plan go to `downloads` once the devices hold them
    simulation::Opened opened;
    multi::SlabDriver& driver;
    simulation::RunState state;
    simulation::Failures failures;
    simulation::StepRunner runner;
    simulation::StepAhead ahead;
    simulation::Downloads downloads;
    render::FrameCache frames;  // the images' kernels and buffers, kept between frames (views.cpp)
    surface::DeviceParts surfaces;  // the surface's buffers and capacities on each device, likewise

    Impl(const Scene& s, const Options& o, const std::function<simulation::Source(const device::Grid&)>& source_of)
        : scene(s),
          options(o),
          grid(detail::grid_of(scene)),
          source(source_of(grid)),
          opened(simulation::open(scene, grid, options, source)),
          driver(*opened.driver),
          failures(scene, options, driver, state),
          runner(scene, driver, state, failures),
          ahead(scene, options, driver, state, failures, runner),
          downloads(driver, state, std::move(source.particles), std::move(source.plan)) {
        const auto& k = opened.first;
        if (k.kick.bad_index >= 0) failures.bad_particle(k);
        state.take(k, driver);
        state.dt_next = simulation::next_dt(scene, driver.params(), k.kick);
        if (source.checkpoint) {
            cl_rt::guarded("restoring the checkpoint", "", [&] {
                driver.restore_owned(*source.checkpoint);
                return 0;
            });
            state.restore(*source.checkpoint);
            state.info.particles = driver.owned();
        }
        source.checkpoint = nullptr;  // the caller's, not ours to keep
        ahead.start();
    }
};

}  // namespace clsph
