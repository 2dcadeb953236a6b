// The step ahead on one device (docs/multi_device.md, "The step ahead"): the same phases as
// SlabDriver::step with nothing coming back until the step's record. The drift's dt comes from
// the device's clock (kernels/step_clock.cl), the settle's counters and the kick's reductions stay
// on the device for end_step, and the cell tables run over a bound (CellPipeline::
// enqueue_tables_bounded). The order of operations on the particles is the synchronous path's
// for one device (Exchange::run: settle, sort of the kept keys, reorder, tables, forces, kick), so
// both give bitwise the same states.
#include "multi/slab_driver.hpp"

namespace clsph::multi {

void SlabDriver::enqueue_step_ahead(std::size_t slot, double* record, cl_rt::EventSet& done) {
    apply_seams();  // tests: a simulated failure
    Slab& s = slabs_[0];
    // Fused (issue 30): the drift in the cell pass's first launch, unless moving solids are put
    // between the two.
    const bool drift_in_cells = !options_.seams.unfused && !s.physics->moves();
    if (!drift_in_cells) {
        s.physics->kick_drift_on_clock(*s.store);
        s.physics->move_solids_on_clock(*s.store);  // moving solids: at the clock's time after the step
    }
    tables_forces_kick_ahead(slot, record, done, drift_in_cells);
    ++steps_;
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
