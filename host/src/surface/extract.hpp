// The free surface of a running simulation (Simulation::surface): the fluid fraction sampled on a
// lattice, in blocks of 8^3 cubes near the free surface only, meshed by marching cubes on the
// device that owns each block, welded into one mesh. Blocks are found from the fluid particles'
// positions: a block is sampled if it or a neighbour holds fluid, unless it and all 26 neighbours
// are nearly full of fluid (inside); blocks never sampled count as inside or outside alike on both
// sides, so the mesh stays closed. Each block belongs to the device owning its first sample's
// column, and each sample is evaluated on the device owning its own column (which holds the ghosts
// it needs), so the mesh is the same on any number of devices. All of it runs on the devices
// (surface/device_surface.hpp); extract_surface() downloads and joins the parts, welded by
// lattice edge where devices meet.
#pragma once
#include "clsph/mesh.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "multi/slab_driver.hpp"
#include "surface/device_surface.hpp"

#include <memory>
#include <vector>

namespace clsph::surface {

// The surface left on the devices: each busy slab's part (null for the others), kept from
// surface to surface by whoever takes them (the Simulation), so each device's buffers and
// capacities are reused.
struct DeviceParts {
    std::vector<std::unique_ptr<DeviceSurface>> parts;
    // Reads each part's totals (DeviceSurface::settle): true when every count fitted; false when a
    // capacity was short (it has grown) and the surface must be taken again.
    bool settle();
    bool empty() const {  // after settle()
        for (const auto& p : parts)
            if (p && p->triangle_count() > 0) return false;
        return true;
    }
};

// The surface into `into` (its parts reused where the device, its physics and the lattice are the
// same), with no read-back on one device: the counts stay on the devices until into.settle().
void surface_on_devices(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                        const SurfaceOptions& options, DeviceParts& into);

// into.settle() on every rank (across ranks: true only if it is true on each, so all redo or none).
bool settle_everywhere(multi::SlabDriver& driver, DeviceParts& into);

// The surface into `into`, taken again until every count fits its capacity (a redo happens on
// the first surface and when the surface outgrows the last one's capacities).
void settled_surface(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                     const SurfaceOptions& options, DeviceParts& into);

TriangleMesh extract_surface(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                             const SurfaceOptions& options, DeviceParts& parts);

}  // namespace clsph::surface
