// The step ahead (simulation/step_ahead.hpp).
#include "simulation/step_ahead.hpp"

#include "cl/errors.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace clsph::simulation {

void StepAhead::start() {
    on_ = driver_.can_step_ahead(options_.synchronous, options_.steps_ahead);
    using Mode = cl_rt::EventSet::Mode;
    wait_mode_ = options_.wait == WaitMode::poll ? Mode::poll : options_.wait == WaitMode::block ? Mode::block : Mode::callbacks;
    if (!on_) return;
    auto& slabs = driver_.slabs();
    const auto points = probes::sample_points(scene_).points;
    probe_points_ = points.size();
    driver_.start_ahead(options_.steps_ahead, points);
    for (std::size_t k = 0; k < options_.steps_ahead; ++k) {
        auto slot = std::make_unique<Slot>();
        slot->record.resize(slabs.size());
        slot->probe.resize(slabs.size());
        for (std::size_t d = 0; d < slabs.size(); ++d) {
            slot->record[d].resize(*slabs[d].device, device::StepRecord::kDoubles);
            slot->probe[d].resize(*slabs[d].device, 2 * points.size());
        }
        ring_.push_back(std::move(slot));
    }
    // dt = cfl min(sqrt(h/|a|), h/(c0 + |v|)) <= cfl h/c0: how far the steps in flight can go at most.
    const auto& sp = driver_.params();
    dt_max_ = scene_.run.fixed_dt > 0 ? scene_.run.fixed_dt
                                    : std::min(scene_.physics.cfl * static_cast<double>(sp.h) / static_cast<double>(sp.c0),
                                               scene_.physics.viscous_dt());
    if (scene_.run.fixed_dt <= 0)
        for (auto& s : slabs) s.physics->set_dt_floor(options_.dt_collapse * dt_max_);
}

bool StepAhead::may_enqueue(double t, std::uint64_t last_step) const {
    const std::size_t j = in_flight_.size();
    if (j >= ring_.size()) return false;
    const std::uint64_t s = state_.info.step + j;  // the last step enqueued (or taken)
    if ((last_step && s >= last_step) || (options_.step_limit && s >= options_.step_limit)) return false;
    // run.list_buffer: not past the build the kept tables will likely need (the steps behind a
    // build halt and are thrown away); the first step in flight is always allowed (the host's
    // builds_next said it keeps the tables).
    if (j > 0 && !driver_.likely_kept(j + 1, state_.dt_next)) return false;
    // run_until takes the next step while the time is short of t; with j steps in flight, the time
    // before the next one is at most j * dt_max_ on.
    return state_.info.time + static_cast<double>(j) * dt_max_ * (1.0 + 1e-9) < t - 1e-12;
}

void StepAhead::enqueue() {
    const std::size_t k = next_slot_;
    next_slot_ = (next_slot_ + 1) % ring_.size();
    const std::uint64_t step = state_.info.step + in_flight_.size() + 1;
    std::vector<double*> records;
    for (auto& r : ring_[k]->record) records.push_back(r.data());
    driver_.enqueue_step_ahead(k, records, ring_[k]->done);
    in_flight_.push_back(k);
    enqueue_probe(k, step);
}

// The probes of a probe step sampled in the queue, on the state after it, so that the step
// callback finds them (sample_probes) with later steps already in flight: each point on the device
// that owns it (SlabDriver::probe_owners).
void StepAhead::enqueue_probe(std::size_t k, std::uint64_t step) {
    auto& slot = *ring_[k];
    slot.probed = probe_step(step);
    if (!slot.probed) return;
    auto& slabs = driver_.slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        auto& s = slabs[d];
        s.physics->enqueue_probe(*s.store, *s.cells, slot.probe[d].data(), slot.done);
        s.device->flush();
    }
}

device::StepRecord StepAhead::combined(Slot& slot) const {
    auto r = device::StepRecord::from(slot.record[0].data());
    for (std::size_t d = 1; d < slot.record.size(); ++d) {
        const auto x = device::StepRecord::from(slot.record[d].data());
        r.halt |= x.halt;  // (every device halts alike)
        r.kick.max_speed2 = std::max(r.kick.max_speed2, x.kick.max_speed2);
        r.kick.max_accel2 = std::max(r.kick.max_accel2, x.kick.max_accel2);
        r.kick.kinetic_energy += x.kick.kinetic_energy;
        r.kick.fluid += x.kick.fluid;
        r.left_domain += x.left_domain;
        r.jumped += x.jumped;
        if (x.kick.bad_index >= 0 && r.kick.bad_index < 0) {
            r.kick.bad_index = x.kick.bad_index;
            r.bad_id = x.bad_id;
            std::copy(std::begin(x.bad_velrho), std::end(x.bad_velrho), std::begin(r.bad_velrho));
        }
    }
    if (slot.record.size() > 1) r.cells = 0;  // (as the synchronous step says on several devices)
    return r;
}

device::StepRecord StepAhead::wait_oldest() {
    const std::size_t k = in_flight_.front();
    in_flight_.pop_front();
    auto& slot = *ring_[k];
    slot.done.wait("a step run ahead", wait_mode_);
    const auto r = combined(slot);
    if (slot.probed && r.halt == 0) {
        probed_.assign(probe_points_, probes::Sums{});
        const auto& owners = driver_.probe_owners();
        for (std::size_t d = 0; d < owners.size(); ++d)
            for (std::size_t j = 0; j < owners[d].size(); ++j)
                probed_[owners[d][j]] = {slot.probe[d][2 * j], slot.probe[d][2 * j + 1]};
        probed_step_ = state_.info.step + 1;  // the step this record is (apply() makes it info's)
    }
    return r;
}

void StepAhead::apply(const device::StepRecord& r) {
    ++taken_;
    state_.info.step += 1;
    state_.info.time += r.dt;
    state_.info.dt = r.dt;
    state_.info.removed += r.left_domain;
    left_pending_ += r.left_domain;
    state_.info.particles = driver_.owned() - left_pending_;
    state_.info.fluid = r.kick.fluid;
    state_.info.kinetic_energy = r.kick.kinetic_energy;
    state_.info.max_speed = std::sqrt(r.kick.max_speed2);
    state_.info.cells = r.cells;
    state_.info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - state_.started).count();
    state_.dt_next = r.next_dt;
    driver_.took_step_ahead(r.dt, r.kick, in_flight_.empty());
    if (driver_.lists().on()) return;  // the tables kept: built by the synchronous steps only
    auto& cells = *driver_.slabs()[0].cells;
    if (in_flight_.empty()) cells.set_counted_cells(r.cells);  // probes read the tables now
    // Grow the tables before the bound is reached (the steps in flight keep the old ones).
    const double grow = 1.0 + 0.5 * options_.cell_headroom;
    if (static_cast<double>(r.cells) * grow > static_cast<double>(cells.cell_capacity()))
        cells.grow_cells(static_cast<std::size_t>(static_cast<double>(r.cells) * grow));
}

void StepAhead::drop_halted(double t, std::size_t already_taken) {
    std::size_t n = already_taken;
    for (; !in_flight_.empty(); ++n) wait_oldest();
    driver_.dropped_steps_ahead(n);
    thrown_ += n;
    driver_.set_clock(state_.info.time, state_.dt_next, t);
}

void StepAhead::settle(bool count) {
    bool bad = false;
    while (!in_flight_.empty()) {
        const auto r = wait_oldest();
        bad = bad || r.halt != 0 || r.kick.bad_index >= 0;
        if (count && !bad) apply(r);
    }
    drop_left();
}

void StepAhead::drop_left() {
    if (left_pending_ == 0 || !in_flight_.empty()) return;
    driver_.drop_left(left_pending_);
    left_pending_ = 0;
}

void StepAhead::run(double t, const std::function<void(const StepInfo&)>& on_step,
                                 std::uint64_t max_steps) {
    const std::uint64_t last = max_steps ? state_.info.step + max_steps : 0;
    drop_left();
    driver_.set_clock(state_.info.time, state_.dt_next, t);
    bool failed = false;
    DeviceError failure(CL_SUCCESS, "");
    for (;;) {
        // run.list_buffer: a step that builds the cell tables is the synchronous one (nothing in
        // flight; end_step halted the steps after the last kept one, kHaltLists).
        if (in_flight_.empty() && !failed && driver_.builds_next(first_dt(t))) {
            if (!may_enqueue(t, last)) break;
            state_.dt_next = first_dt(t);  // as run_until lands on t
            // The last step taken ahead halted every device for this build (its end_step saw the
            // bound reach half the buffer), unless the host held back the steps behind it: the
            // synchronous step's kernels must run.
            driver_.clear_halts();
            runner_.step();
            driver_.set_clock(state_.info.time, state_.dt_next, t);
            if (on_step) on_step(state_.info);  // (nothing in flight: the state is this step's)
            continue;
        }
        while (!failed && may_enqueue(t, last)) {
            try {
                // What the bindings throw (a cl::Error from setArg, say) is a DeviceError too.
                cl_rt::guarded("taking a step", "", [&] { enqueue(); });
            } catch (const DeviceError& e) {
                failed = true;  // reported once the steps before it are taken, as the synchronous path does
                failure = e;
            }
        }
        if (in_flight_.empty()) break;
        device::StepRecord r;
        try {
            r = cl_rt::guarded("waiting for a step", "", [&] { return wait_oldest(); });
        } catch (const DeviceError& e) {
            in_flight_.clear();  // the device's state is lost: the step after the last one taken failed
            failures_.device_failed(e, std::min(state_.dt_next, std::max(t - state_.info.time, 1e-12)));
        }
        if (r.halt & device::kHaltCells) {
            // More non-empty cells than the tables hold: this step and the ones after it changed
            // nothing (kernels/step_clock.cl). Grow the tables and take this step again.
            const std::size_t dropped = in_flight_.size();
            thrown_ += dropped + 1;
            while (!in_flight_.empty()) wait_oldest();
            next_slot_ = 0;
            in_flight_.push_back(next_slot_);
            next_slot_ = 1 % ring_.size();
            driver_.redo_step_ahead(r.cells, dropped, 0, ring_[0]->record[0].data(), ring_[0]->done);
            enqueue_probe(0, state_.info.step + 1);
            continue;
        }
        if (r.halt & device::kHaltLists) {
            // The tables must be built before this step: it and those after it changed nothing.
            drop_halted(t, 1);
            continue;
        }
        if (r.halt != 0) {  // past an event or a failure: nothing happened
            driver_.dropped_steps_ahead(1);
            ++thrown_;
            continue;
        }
        if (r.kick.bad_index >= 0) {
            settle(false);
            failures_.bad_particle(r.bad_id, r.bad_velrho, r.dt, std::string());
        }
        apply(r);
        try {
            failures_.check_dt_collapse();
        } catch (const SimulationError&) {
            settle(false);
            throw;
        }
        if (!on_step) continue;
        try {
            on_step(state_.info);
        } catch (...) {
            settle(true);  // the state is the last step's: info follows it
            throw;
        }
    }
    drop_left();
    if (failed) failures_.device_failed(failure, std::min(state_.dt_next, std::max(t - state_.info.time, 1e-12)));
}

}  // namespace clsph::simulation
