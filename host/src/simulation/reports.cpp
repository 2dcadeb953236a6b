// What the Simulation reports of its devices: names, shares of the domain, per-kernel times and
// traces, host phases, memory.
#include "simulation/impl.hpp"

namespace clsph {

std::vector<std::string> Simulation::device_names() const {
    std::vector<std::string> names;
    for (const auto& d : impl_->opened.devices) names.push_back(d->label());
    return names;
}

std::vector<DeviceShare> Simulation::shares() const {
    std::vector<DeviceShare> out;
    auto& driver = impl_->driver;
    auto& slabs = driver.slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;  // across ranks: this rank's
        auto& s = slabs[d];
        out.push_back({s.device->label(), s.store->ranges.owned, s.first_col, s.end_col, s.force_seconds,
                       s.store->ranges.ghosts_before + s.store->ranges.ghosts_after, s.received_bytes,
                       s.split_passes, s.calibration.fixed + s.calibration.per_unit * s.calibration.work_total, s.calibration.fixed,
                       s.physics->interaction(), driver.cell_order()});
    }
    return out;
}

CellOrder Simulation::cell_order() const { return impl_->driver.cell_order(); }

TableBuilds Simulation::table_builds() const {
    const auto& lists = impl_->driver.lists();
    return {lists.builds(), lists.age(), lists.moved()};
}

std::vector<KernelTime> Simulation::profile() {
    std::vector<KernelTime> out;
    for (auto& d : impl_->opened.devices)
        for (const auto& [name, st] : d->profiler().stats()) out.push_back({name, d->label(), st.calls, st.seconds});
    return out;
}

std::vector<CommandSpan> Simulation::take_trace() {
    std::vector<CommandSpan> out;
    for (auto& d : impl_->opened.devices)
        for (auto& t : d->profiler().take_trace()) out.push_back({d->label(), std::move(t.name), t.start, t.end});
    return out;
}

std::vector<KernelTime> Simulation::host_phases() const {
    std::vector<KernelTime> out;
    for (const auto& [name, seconds] : impl_->driver.phase_seconds()) out.push_back({name, {}, impl_->state.info.step, seconds});
    return out;
}

std::vector<MemoryReport> Simulation::memory() const {
    std::vector<MemoryReport> out;
    auto& driver = impl_->driver;
    auto& slabs = driver.slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;  // across ranks: this rank's
        auto& s = slabs[d];
        MemoryReport r;
        r.device = s.device->label();
        r.particles = s.store->ranges.owned;
        r.peak_bytes = s.device->memory().counters().peak;
        r.capacity_particles = s.store->capacity();
        r.peak_buffers = s.device->memory().at_peak();
        out.push_back(r);
    }
    return out;
}

}  // namespace clsph
