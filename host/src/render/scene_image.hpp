// An image of a simulation: the free surface drawn by the devices, each the triangles over its own
// slab, solid boxes grey on the first device, the walls' outlines as lines, composited by depth.
#pragma once
#include "clsph/mesh.hpp"
#include "clsph/render.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "multi/slab_driver.hpp"
#include "render/frame_cache.hpp"
#include "scene/motion.hpp"
#include "surface/extract.hpp"

namespace clsph::render {

// Solid boxes as 12 triangles each with face normals (outwards); the walls' edges as lines.
TriangleMesh box_mesh(const std::vector<SolidBox>& boxes);
std::vector<std::array<Vec3, 2>> wall_lines(const std::vector<BoxWalls>& walls);

Image render_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const TriangleMesh& surface,
                   const CameraView& camera, const ImageStyle& style = {});
// The same from the surface where the devices made it (surface::surface_on_devices): each device
// draws its own part from its own memory; only the images move.
// `poses`: where each of scene.solids is now (a moving or floating box; empty: every box at rest).
Image render_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                   const surface::DeviceParts& surface, const CameraView& camera, const ImageStyle& style,
                   FrameCache& cache, const std::vector<scene::RigidPose>& poses);

// The same picture with the water drawn by splats (render.method "splat", render/splat.hpp): no mesh;
// `style` by a field colours the splats (by_device: drawn as uniform).
Image splat_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const CameraView& camera,
                  const ImageStyle& style, FrameCache& cache, const std::vector<scene::RigidPose>& poses);

// The solid boxes as a layer on `device`: at rest, the cache's (uploaded once); moved (`poses`),
// their triangles turned and moved, uploaded into `moved`.
DeviceLayer solids_layer(FrameCache& cache, cl_rt::Device& device, const Scene& scene,
                         const std::vector<scene::RigidPose>& poses, UploadedLayer& moved);

}  // namespace clsph::render
