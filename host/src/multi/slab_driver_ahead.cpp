// The step ahead (docs/multi_device.md, "The step ahead"): the same phases as SlabDriver::step
// with nothing coming back until the step's record; on several devices the kept steps only
// (run.list_buffer), whose copies between devices the Relay orders on the devices' queues. The drift's dt comes from
// the device's clock (kernels/step_clock.cl), the settle's counters and the kick's reductions stay
// on the device for end_step, and the cell tables run over a bound (CellPipeline::
// enqueue_tables_bounded). The order of operations on the particles is the synchronous path's
// for one device (Exchange::run: settle, sort of the kept keys, reorder, tables, forces, kick), so
// both give bitwise the same states.
#include "multi/slab_driver.hpp"

namespace clsph::multi {

void SlabDriver::start_ahead(std::size_t slots, const std::vector<std::array<double, 3>>& probe_points) {
    const std::size_t D = slabs_.size();
    slots_ = slots;
    for (auto& s : slabs_) {
        s.physics->set_slabs(D, slots);
        s.physics->set_half_buffer(lists_.half_buffer());
    }
    if (D > 1 && !relay_) relay_ = std::make_unique<cl_rt::Relay>();
    probe_points_ = probe_points;
    probe_owners_.clear();
    if (D == 1) {
        slabs_[0].physics->set_probe_points(probe_points_);
        probe_owners_.assign(1, {});
        for (std::size_t i = 0; i < probe_points_.size(); ++i) probe_owners_[0].push_back(i);
    }
}

void SlabDriver::set_clock(double time, double next_dt, double event) {
    // The kept tables' bound goes on from the host's, the first step's own included: end_step adds
    // each next step's before it is taken, and the host asked builds_next() for the first one.
    const double dt = std::min(next_dt, std::max(event - time, 1e-12));  // as Physics::set_clock
    const double moved = lists_.on() ? lists_.moved_after(dt, last_kick_.max_speed2, last_kick_.max_accel2) : 0.0;
    for (auto& s : slabs_) {
        s.physics->set_clock(time, next_dt, event, moved);
        if (lists_.on()) s.cells->store_count();
    }
    if (lists_.on() && slabs_.size() > 1) {
        // Every staging block the copies ahead use, made now, with nothing in flight (mapping one
        // waits for its device's queue, which the steps ahead tie to the other devices').
        exchange_->prepare_keep_ahead();
        const std::size_t D = slabs_.size();
        for (std::size_t slot = 0; slot < slots_; ++slot)
            for (std::size_t d = 0; d < D; ++d)
                for (std::size_t e = 0; e < D; ++e) {
                    if (d == e || cl_rt::Relay::same_context(*slabs_[d].device, *slabs_[e].device)) continue;
                    auto& staging = sums_staging_[{d, e, slot}];
                    if (!staging) staging = std::make_unique<cl_rt::PinnedHost>();
                    staging->reserve(*slabs_[d].device, device::Physics::kStepSumBytes);
                }
    }
    if (slabs_.size() == 1 || probe_points_.empty()) return;
    // Each point on the slab that owns its column (as probe() does), for the cuts as they are now:
    // the steps ahead keep them.
    std::vector<std::vector<std::size_t>> owners(slabs_.size());
    const device::Grid& grid = partition_.grid();
    for (std::size_t i = 0; i < probe_points_.size(); ++i) {
        std::array<float, 3> off{};
        const auto key = grid.locate(probe_points_[i], off);
        if (key != grid.params().invalid_key) owners[partition_.owner_of(key, slabs_)].push_back(i);
    }
    if (owners == probe_owners_) return;
    probe_owners_ = owners;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        std::vector<std::array<double, 3>> pts;
        for (auto i : owners[d]) pts.push_back(probe_points_[i]);
        slabs_[d].physics->set_probe_points(pts);
    }
}

void SlabDriver::took_step_ahead(double dt, const device::KickResult& kick, bool idle) {
    if (lists_.on()) lists_.kept(dt, last_kick_.max_speed2, last_kick_.max_accel2);
    last_kick_ = kick;
    if (idle) read_force_times();  // the balancer's input for the next build
}

void SlabDriver::clear_halts() {
    for (auto& s : slabs_) s.physics->clear_halt();
}

void SlabDriver::enqueue_step_ahead(std::size_t slot, const std::vector<double*>& records, cl_rt::EventSet& done) {
    apply_seams();  // tests: a simulated failure
    if (lists_.on()) {
        kept_step_ahead(slot, records, done);
        ++steps_;
        return;
    }
    Slab& s = slabs_[0];
    // Fused (issue 30): the drift in the cell pass's first launch, unless moving solids are put
    // between the two.
    const bool drift_in_cells = !options_.seams.unfused && !s.physics->moves();
    if (!drift_in_cells) {
        s.physics->kick_drift_on_clock(*s.store);
        s.physics->move_solids_on_clock(*s.store);  // moving solids: at the clock's time after the step
    }
    tables_forces_kick_ahead(slot, records[0], done, drift_in_cells);
    ++steps_;
}

// The synchronous kept step (SlabDriver::step_here, Exchange::keep) with nothing coming back: the
// drift on each device's clock, the ghosts brought up to date device to device (Exchange::
// keep_ahead), the force pass and the kick, then each device's part of the reductions to every
// other device, and end_step on each: every device takes the same next step, or all halt.
void SlabDriver::kept_step_ahead(std::size_t slot, const std::vector<double*>& records, cl_rt::EventSet& done) {
    const std::size_t D = slabs_.size();
    for (auto& s : slabs_) s.physics->keep_tables(true);
    exchange_->keep_ahead(
        relay_.get(),
        [&](std::size_t d) {
            forces(d);
            Slab& s = slabs_[d];
            s.physics->enqueue_kick_on_clock(*s.store);
            if (D > 1) s.physics->enqueue_step_sums(slot, d);
        },
        [&](std::size_t d) { slabs_[d].physics->kick_drift_on_clock(*slabs_[d].store); });
    for (std::size_t e = 0; e < D; ++e)
        for (std::size_t d = 0; d < D; ++d) {
            if (d == e) continue;
            const std::size_t at = (slot * D + d) * device::Physics::kStepSumBytes;
            auto& staging = sums_staging_[{d, e, slot}];
            if (!staging) staging = std::make_unique<cl_rt::PinnedHost>();  // (one context: unused)
            relay_->copy(*slabs_[d].device, *slabs_[e].device,
                         {{&slabs_[d].physics->step_sums(), &slabs_[e].physics->step_sums(), device::Physics::kStepSumBytes,
                           at, at}},
                         *staging);
        }
    for (std::size_t e = 0; e < D; ++e) {
        Slab& s = slabs_[e];
        s.physics->enqueue_end_step(*s.store, *s.cells, slot, records[e], done);
        s.device->flush();
        if (s.device->profiler().enabled()) s.device->profiler().collect_finished();
    }
}

void SlabDriver::redo_step_ahead(std::size_t cells, std::size_t uncounted, std::size_t slot, double* record,
                                 cl_rt::EventSet& done) {
    Slab& s = slabs_[0];
    steps_ -= uncounted;
    s.cells->grow_cells(cells);
    s.physics->clear_halt();
    tables_forces_kick_ahead(slot, record, done, false);
}

void SlabDriver::tables_forces_kick_ahead(std::size_t slot, double* record, cl_rt::EventSet& done, bool drift) {
    Slab& s = slabs_[0];
    auto& ps = *s.store;
    const std::size_t n = ps.ranges.active();
    const device::KeyRange keys = partition_.keys_of(partition_.needs(slabs_)[0]);
    // Settling an offset already inside its cell leaves it alone, and a stable sort of sorted keys
    // moves nothing: a halted step (kernels/step_clock.cl) changes nothing here either.
    if (drift) {
        s.cells->enqueue_drift_sort_keys(ps, keys, s.physics->drift_on_clock());
    } else {
        s.cells->enqueue_settle_on_device(ps, keys);
        s.cells->enqueue_sort_keys(ps, device::SortSelection{n, ps.ranges.first_owned(), ps.ranges.end_owned(), n, keys, false});
    }
    s.cells->enqueue_reorder(ps, n, 0);
    s.cells->enqueue_tables_bounded(ps, n, s.physics->halt());
    forces(0);
    s.physics->enqueue_kick_on_clock(ps);
    s.physics->enqueue_end_step(ps, *s.cells, slot, record, done);
    s.device->flush();
    if (s.device->profiler().enabled()) s.device->profiler().collect_finished();
}

}  // namespace clsph::multi
