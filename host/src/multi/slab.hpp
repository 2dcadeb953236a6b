// One device's part of the run: its columns of the domain, its particles and the per-device parts
// that work on them (docs/multi_device.md).
#pragma once
#include "cl/device.hpp"
#include "device/cell_pipeline.hpp"
#include "device/inlet_zones.hpp"
#include "device/outlet_zones.hpp"
#include "device/particle_arrays.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"
#include "multi/force_timer.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace clsph::multi {

struct Slab {
    cl_rt::Device* device = nullptr;
    std::unique_ptr<device::ParticleStore> store;  // [ghosts | owned | ghosts], sorted
    std::unique_ptr<device::CellPipeline> cells;
    std::unique_ptr<device::Physics> physics;
    std::unique_ptr<ForceTimer> force_timer;
    std::unique_ptr<device::InletZones> inlets;  // null: the scene has no inlet
    std::unique_ptr<device::OutletZones> outlets;  // null: no outlet has a zone
    std::size_t first_col = 0, end_col = 0;  // owned columns [first_col, end_col)
    double force_seconds = 0;                // last step's force pass (the balancer's input)
    std::size_t received_bytes = 0;          // copied in from other devices since the start
    // The halo overlapped with the interior (Exchange::Interior): the owned particles whose forces
    // of the pass that ran before the arrivals came stand, set by the exchange after the merge
    // ([0, 0): none, the pass is whole), and the passes so split since the start.
    std::size_t interior_first = 0, interior_end = 0;
    std::size_t split_passes = 0;
    // Where each owned column [columns_first, columns_end] began in the sorted particles after the
    // last exchange: the next exchange's windows and the balancer's column profile. Empty: unknown.
    std::vector<std::uint32_t> column_at;
    std::size_t columns_first = 0, columns_end = 0;
    // The exchange's device-side blocks: what this device sends (packed per receiver), what it
    // receives (left senders first).
    device::ParticleArrays outbox, inbox;
    // The calibration before the first step (several devices, dynamic balance): force pass time =
    // fixed + per_unit * work, and the scene's whole work (so per_unit * work_total is the time
    // this device would take for everything).
    struct Calibration { double fixed = 0, per_unit = 0, work_total = 0; } calibration;

    bool empty() const { return first_col >= end_col; }
    bool busy() const { return !empty() || store->ranges.active() > 0; }
    bool columns_known() const { return !column_at.empty() && column_at.size() == columns_end - columns_first + 1; }
};

}  // namespace clsph::multi
