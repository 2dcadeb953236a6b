// Steps run ahead of the host on one device (docs/multi_device.md, "The step ahead"): up to
// Options::steps_ahead steps are enqueued at once, each choosing its dt on the device
// (kernels/step_clock.cl) and leaving its record in a ring of pinned slots; the host takes the
// records in order, a few steps behind, and runs the step callback for each. It waits for the
// device only at events: a frame or --until (run_until's t), the step limit, and the last steps
// before t, where it cannot be sure the next step is still needed. Probe steps sample the probes
// in the queue (enqueue_probe), so the callback finds them without a wait.
#include "simulation_impl.hpp"
#include "cl/errors.hpp"

#include <algorithm>
#include <cmath>

namespace clsph {

void Simulation::Impl::setup_ahead() {
    ahead = !options.synchronous && options.steps_ahead > 0 && driver->can_step_ahead();
    using Mode = cl_rt::EventSet::Mode;
    wait_mode = options.wait == WaitMode::poll ? Mode::poll : options.wait == WaitMode::block ? Mode::block : Mode::callbacks;
    if (!ahead) return;
    auto& device = *driver->slabs()[0].device;
    const auto points = probe_points().points;
    driver->slabs()[0].physics->set_probe_points(points);
    for (std::size_t k = 0; k < options.steps_ahead; ++k) {
        ring.push_back(std::make_unique<Slot>());
        ring.back()->record.resize(device, device::StepRecord::kDoubles);
        ring.back()->probe.resize(device, 2 * points.size());
    }
    // dt = cfl min(sqrt(h/|a|), h/(c0 + |v|)) <= cfl h/c0: how far the steps in flight can go at most.
    const auto& sp = driver->params();
    dt_max = scene.run.fixed_dt > 0 ? scene.run.fixed_dt
                                    : scene.physics.cfl * static_cast<double>(sp.h) / static_cast<double>(sp.c0);
    if (scene.run.fixed_dt <= 0) driver->slabs()[0].physics->set_dt_floor(options.dt_collapse * dt_max);
}

bool Simulation::Impl::may_enqueue(double t, std::uint64_t last_step) const {
    const std::size_t j = in_flight.size();
    if (j >= ring.size()) return false;
    const std::uint64_t s = info.step + j;  // the last step enqueued (or taken)
    if ((last_step && s >= last_step) || (options.step_limit && s >= options.step_limit)) return false;
    // run_until takes the next step while the time is short of t; with j steps in flight, the time
    // before the next one is at most j * dt_max on.
    return info.time + static_cast<double>(j) * dt_max * (1.0 + 1e-9) < t - 1e-12;
}

void Simulation::Impl::enqueue_ahead() {
    const std::size_t k = next_slot;
    next_slot = (next_slot + 1) % ring.size();
    const std::uint64_t step = info.step + in_flight.size() + 1;
    driver->enqueue_step_ahead(k, ring[k]->record.data(), ring[k]->done);
    in_flight.push_back(k);
    enqueue_probe(k, step);
}

// The probes of a probe step sampled in the queue, on the state after it, so that the step
// callback finds them (sample_probes) with later steps already in flight.
void Simulation::Impl::enqueue_probe(std::size_t k, std::uint64_t step) {
    auto& slot = *ring[k];
    slot.probed = probe_step(step);
    if (!slot.probed) return;
    auto& s = driver->slabs()[0];
    s.physics->enqueue_probe(*s.store, *s.cells, slot.probe.data(), slot.done);
    s.device->flush();
}

device::StepRecord Simulation::Impl::wait_oldest() {
    const std::size_t k = in_flight.front();
    in_flight.pop_front();
    auto& slot = *ring[k];
    slot.done.wait("a step run ahead", wait_mode);
    const auto r = device::StepRecord::from(slot.record.data());
    if (slot.probed && r.halt == 0) {
        probed.resize(slot.probe.size() / 2);
        for (std::size_t i = 0; i < probed.size(); ++i) probed[i] = {slot.probe[2 * i], slot.probe[2 * i + 1]};
        probed_step = info.step + 1;  // the step this record is (apply() makes it info's)
    }
    return r;
}

void Simulation::Impl::apply(const device::StepRecord& r) {
    info.step += 1;
    info.time += r.dt;
    info.dt = r.dt;
    info.removed += r.left_domain;
    left_pending += r.left_domain;
    info.particles = driver->owned() - left_pending;
    info.fluid = r.kick.fluid;
    info.kinetic_energy = r.kick.kinetic_energy;
    info.max_speed = std::sqrt(r.kick.max_speed2);
    info.cells = r.cells;
    info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    dt_next = r.next_dt;
    auto& cells = *driver->slabs()[0].cells;
    if (in_flight.empty()) cells.set_counted_cells(r.cells);  // probes read the tables now
    // Grow the tables before the bound is reached (the steps in flight keep the old ones).
    const double grow = 1.0 + 0.5 * options.cell_headroom;
    if (static_cast<double>(r.cells) * grow > static_cast<double>(cells.cell_capacity()))
        cells.grow_cells(static_cast<std::size_t>(static_cast<double>(r.cells) * grow));
}

void Simulation::Impl::settle_in_flight(bool count) {
    bool bad = false;
    while (!in_flight.empty()) {
        const auto r = wait_oldest();
        bad = bad || r.halt != 0 || r.kick.bad_index >= 0;
        if (count && !bad) apply(r);
    }
    drop_left();
}

void Simulation::Impl::drop_left() {
    if (left_pending == 0 || !in_flight.empty()) return;
    driver->drop_left(left_pending);
    left_pending = 0;
}

void Simulation::Impl::run_ahead(double t, const std::function<void(const StepInfo&)>& on_step,
                                 std::uint64_t max_steps) {
    const std::uint64_t last = max_steps ? info.step + max_steps : 0;
    drop_left();
    driver->set_clock(info.time, dt_next, t);
    bool failed = false;
    DeviceError failure(CL_SUCCESS, "");
    for (;;) {
        while (!failed && may_enqueue(t, last)) {
            try {
                // What the bindings throw (a cl::Error from setArg, say) is a DeviceError too.
                cl_rt::guarded("taking a step", "", [&] { enqueue_ahead(); });
            } catch (const DeviceError& e) {
                failed = true;  // reported once the steps before it are taken, as the synchronous path does
                failure = e;
            }
        }
        if (in_flight.empty()) break;
        device::StepRecord r;
        try {
            r = cl_rt::guarded("waiting for a step", "", [&] { return wait_oldest(); });
        } catch (const DeviceError& e) {
            in_flight.clear();  // the device's state is lost: the step after the last one taken failed
            device_failed(e, std::min(dt_next, std::max(t - info.time, 1e-12)));
        }
        if (r.halt & device::kHaltCells) {
            // More non-empty cells than the tables hold: this step and the ones after it changed
            // nothing (kernels/step_clock.cl). Grow the tables and take this step again.
            const std::size_t dropped = in_flight.size();
            while (!in_flight.empty()) wait_oldest();
            next_slot = 0;
            in_flight.push_back(next_slot);
            next_slot = 1 % ring.size();
            driver->redo_step_ahead(r.cells, dropped, 0, ring[0]->record.data(), ring[0]->done);
            enqueue_probe(0, info.step + 1);
            continue;
        }
        if (r.halt != 0) continue;  // past an event or a failure: nothing happened
        if (r.kick.bad_index >= 0) {
            settle_in_flight(false);
            fail_with(r.bad_id, r.bad_velrho, r.dt, std::string());
        }
        apply(r);
        try {
            check_dt_collapse();
        } catch (const SimulationError&) {
            settle_in_flight(false);
            throw;
        }
        if (!on_step) continue;
        try {
            on_step(info);
        } catch (...) {
            settle_in_flight(true);  // the state is the last step's: info follows it
            throw;
        }
    }
    drop_left();
    if (failed) device_failed(failure, std::min(dt_next, std::max(t - info.time, 1e-12)));
}

}  // namespace clsph
