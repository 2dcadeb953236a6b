// Closed triangle meshes (Wavefront OBJ) sampled onto the dp lattice.
#pragma once
#include "clsph/scene.hpp"
#include "scene/mesh_obj.hpp"

#include <vector>

namespace clsph::scene {

// Scale, then rotate (about x, then y, then z, through the origin), then translate: where the
// mesh's vertices lie in the scene. Multiples of 90 degrees rotate exactly.
void place_mesh(TriangleMesh& mesh, const MeshObject& m);

// Lattice points (multiples of dp) inside the mesh (after place_mesh): when m.fluid,
// all of them go to `fluid`; otherwise those within m.layers * dp of the surface go to `boundary`.
// Throws SceneError naming the file when it cannot be read or is not a closed triangle mesh.
void sample_mesh(const MeshObject& m, double dp, std::vector<Vec3>& boundary, std::vector<Vec3>& fluid);

}  // namespace clsph::scene
