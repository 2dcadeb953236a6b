// Closed triangle meshes (Wavefront OBJ) sampled onto the dp lattice.
#pragma once
#include "clsph/scene.hpp"

#include <vector>

namespace clsph::scene {

// Lattice points (multiples of dp) inside the mesh (after scale, then translate): when m.fluid,
// all of them go to `fluid`; otherwise those within m.layers * dp of the surface go to `boundary`.
// Throws SceneError naming the file when it cannot be read or is not a closed triangle mesh.
void sample_mesh(const MeshObject& m, double dp, std::vector<Vec3>& boundary, std::vector<Vec3>& fluid);

}  // namespace clsph::scene
