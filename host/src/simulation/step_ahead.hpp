// Steps run ahead of the host (docs/multi_device.md, "The step ahead"; on several devices with the
// cell tables kept over steps, "The step ahead on several devices"): up to
// Options::steps_ahead steps are enqueued at once, each choosing its dt on the device
// (kernels/step_clock.cl) and leaving its record in a ring of pinned slots; the host takes the
// records in order, a few steps behind, and runs the step callback for each. It waits for the
// device only at events: a frame or --until (run's t), the step limit, and the last steps before
// t, where it cannot be sure the next step is still needed. Probe steps sample the probes in the
// queue, so the callback finds them (probed()) without a wait. With run.list_buffer the steps that
// build the cell tables are taken synchronously (StepRunner), with nothing in flight.
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "clsph/options.hpp"
#include "clsph/scene.hpp"
#include "device/physics.hpp"
#include "multi/slab_driver.hpp"
#include "probes/gauges.hpp"
#include "simulation/failures.hpp"
#include "simulation/run_state.hpp"
#include "simulation/step_runner.hpp"

#include <cstdint>
#include <algorithm>
#include <deque>
#include <functional>
#include <memory>
#include <vector>

namespace clsph::simulation {

class StepAhead {
public:
    StepAhead(const Scene& scene, const Options& options, multi::SlabDriver& driver, RunState& state,
              const Failures& failures, StepRunner& runner)
        : scene_(scene), options_(options), driver_(driver), state_(state), failures_(failures), runner_(runner) {}
    // After the set-up (and a checkpoint's restore): on where Options and the driver allow it.
    void start();
    bool on() const { return on_; }
    bool idle() const { return in_flight_.empty(); }
    // Steps taken ahead of the host since the start (not the synchronous ones: table builds,
    // exchanges between devices).
    std::uint64_t taken() const { return taken_; }
    // Steps computed ahead and thrown away: behind a step that halted (a build due, the tables
    // full) or past an event.
    std::uint64_t thrown() const { return thrown_; }
    // Steps to time t (at most max_steps; 0: no limit), every step's record taken in order.
    void run(double t, const std::function<void(const StepInfo&)>& on_step, std::uint64_t max_steps);
    // With nothing in flight: the particles that left the domain, dropped from the arrays.
    void drop_left();
    // The probe sums the queue took after the step the state is at, if that was a probe step for
    // `points` points; null otherwise.
    const std::vector<probes::Sums>* probed(std::size_t points) const {
        return on_ && probed_step_ == state_.info.step && probed_.size() == points ? &probed_ : nullptr;
    }

private:
    struct Slot {
        std::deque<cl_rt::PinnedArray<double>> record;  // per device (a deque: they stay put)
        std::deque<cl_rt::PinnedArray<float>> probe;     // per device: the sums of the points it owns, after a probe step
        bool probed = false;
        cl_rt::EventSet done;
    };
    bool probe_step(std::uint64_t step) const {
        return !scene_.probes.empty() && scene_.run.probe_every > 0 &&
               step % static_cast<std::uint64_t>(scene_.run.probe_every) == 0;
    }
    bool may_enqueue(double t, std::uint64_t last_step) const;
    void enqueue();
    void enqueue_probe(std::size_t slot, std::uint64_t step);
    device::StepRecord wait_oldest();
    // The records of every device as one, as SlabDriver::reductions adds up the synchronous step's.
    device::StepRecord combined(Slot& slot) const;
    // The next step's dt as run_until clamps it to t.
    double first_dt(double t) const { return std::min(state_.dt_next, std::max(t - state_.info.time, 1e-12)); }
    // Waits for every step in flight, all of which halted (changed nothing), and sets the clocks again.
    void drop_halted(double t, std::size_t already_taken);
    void apply(const device::StepRecord& r);
    // Waits for the steps in flight; `count`: taken into the state (no callbacks), else dropped.
    void settle(bool count);

    const Scene& scene_;
    const Options& options_;
    multi::SlabDriver& driver_;
    RunState& state_;
    const Failures& failures_;
    StepRunner& runner_;
    bool on_ = false;
    cl_rt::EventSet::Mode wait_mode_ = cl_rt::EventSet::Mode::callbacks;
    std::vector<std::unique_ptr<Slot>> ring_;
    std::deque<std::size_t> in_flight_;  // ring slots, oldest first
    std::size_t next_slot_ = 0;
    std::size_t left_pending_ = 0;       // particles that left the domain, still at the end of the arrays
    double dt_max_ = 0.0;                // no step is longer (the acoustic limit at rest, or fixed_dt)
    std::size_t probe_points_ = 0;       // probes::sample_points' count
    std::vector<probes::Sums> probed_;   // the sums after step probed_step_
    std::uint64_t probed_step_ = ~std::uint64_t{0};
    std::uint64_t taken_ = 0, thrown_ = 0;
};

}  // namespace clsph::simulation
