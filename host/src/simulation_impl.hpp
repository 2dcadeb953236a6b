// What clsph::Simulation holds (simulation.cpp: the facade; step_ahead.cpp: steps run ahead of
// the host on one device).
#pragma once
#include "clsph/simulation.hpp"

#include "cl/async.hpp"
#include "cl/device.hpp"
#include "clsph/checkpoint.hpp"
#include "clsph/error.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"
#include "multi/slab_driver.hpp"
#include "probes/gauges.hpp"
#include "scene/lattice_plan.hpp"

#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace clsph {

struct Simulation::Impl {
    Scene scene;
    Options options;
    std::vector<std::unique_ptr<cl_rt::Device>> devices;
    device::Grid grid;
    std::unique_ptr<multi::SlabDriver> driver;
    StepInfo info;
    double dt_next = 0.0;
    Particles last_good;  // set-up on the devices: empty until a download (last_good() builds it from plan)
    std::optional<scene::LatticePlan> plan;  // set-up on the devices: the scene's particles, described
    double last_good_time = 0.0;
    std::size_t fluid_total = 0;
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

    Impl(const Scene& s, const Options& o)
        : scene(s),
          options(o),
          grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), s.domain.split_axis, s.domain.periodic,
               device::reach_for(s.physics.support(), s.physics.dp)) {}

    double next_dt(const device::KickResult& k) const {
        if (scene.run.fixed_dt > 0) return scene.run.fixed_dt;
        const auto& sp = driver->params();
        const double h = sp.h;
        const double amax = std::sqrt(k.max_accel2), vmax = std::sqrt(k.max_speed2);
        // Monaghan's force and acoustic (CFL) limits: dt = cfl min(sqrt(h/|a|max), h/(c0 + |v|max)).
        // kernels/step_clock.cl does the same in double on the device (the step ahead).
        const double dt_force = amax > 0 ? std::sqrt(h / amax) : std::numeric_limits<double>::infinity();
        const double dt_sound = h / (sp.c0 + vmax);
        return scene.physics.cfl * std::min(dt_force, dt_sound);
    }

    // The constructors: the devices, the driver and the first force pass; with a checkpoint, its
    // arrays and counters in place of what the first pass left.
    // `plan`: set-up on the devices (p unused), else p uploaded.
    void init(const Particles& p, const Checkpoint* c, const scene::LatticePlan* plan = nullptr);
    void restore(const Checkpoint& c);

    void one_process(const char* what) const;
    void checkpoint_across_ranks(Checkpoint& c);  // every rank's slabs, in slab order (collective)  // throws across MPI ranks: what is not supported there yet
    // The synchronous path's failure: the particle read from the device now.
    [[noreturn]] void fail(const multi::StepOutcome& k);
    // Both paths: `id` the id word, `vr` velocity and density of the particle that failed in the
    // step after info (whose dt was `dt`).
    [[noreturn]] void fail_with(std::uint32_t id, const float vr[4], double dt, const std::string& device);

    // A CFL step below Options::dt_collapse of the acoustic step at rest: both paths stop there
    // with the error a blow-up gives. Event clamps do not count: only the CFL step is checked.
    void check_dt_collapse();
    // The probe points of the scene, each probe's first, and the height probes' spacing.
    using ProbePoints = probes::Points;
    ProbePoints probe_points() const;

    // The step ahead (step_ahead.cpp).
    struct Slot {
        cl_rt::PinnedArray<double> record;
        cl_rt::PinnedArray<float> probe;  // the probe sums, after a probe step
        bool probed = false;
        cl_rt::EventSet done;
    };
    std::vector<std::array<float, 2>> probed;  // the sums after step probed_step
    std::uint64_t probed_step = ~std::uint64_t{0};
    bool probe_step(std::uint64_t step) const {
        return !scene.probes.empty() && scene.run.probe_every > 0 && step % static_cast<std::uint64_t>(scene.run.probe_every) == 0;
    }
    void enqueue_probe(std::size_t slot, std::uint64_t step);
    bool ahead = false;
    cl_rt::EventSet::Mode wait_mode = cl_rt::EventSet::Mode::callbacks;
    std::vector<std::unique_ptr<Slot>> ring;
    std::deque<std::size_t> in_flight;  // ring slots, oldest first
    std::size_t next_slot = 0;
    std::size_t left_pending = 0;       // particles that left the domain, still at the end of the arrays
    double dt_max = 0.0;                // no step is longer (the acoustic limit at rest, or fixed_dt)
    void setup_ahead();
    // Steps to time t (at most max_steps; 0: no limit), every step's record taken in order.
    void run_ahead(double t, const std::function<void(const StepInfo&)>& on_step, std::uint64_t max_steps);
    bool may_enqueue(double t, std::uint64_t last_step) const;
    void enqueue_ahead();
    device::StepRecord wait_oldest();
    void apply(const device::StepRecord& r);
    // Waits for the steps in flight; `count`: taken into info (no callbacks), else dropped.
    void settle_in_flight(bool count);
    void drop_left();                   // with nothing in flight: the particles that left, dropped
    [[noreturn]] void device_failed(const DeviceError& e, double dt);
};

}  // namespace clsph
