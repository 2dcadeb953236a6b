// An image of a simulation: the free surface drawn by the devices, each the triangles over its own
// slab, solid boxes grey on the first device, the walls' outlines as lines, composited by depth.
#pragma once
#include "clsph/mesh.hpp"
#include "clsph/render.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "multi/slab_driver.hpp"

namespace clsph::render {

Image render_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const TriangleMesh& surface,
                   const CameraView& camera, const ImageStyle& style = {});

}  // namespace clsph::render
