// Where each boundary particle's ghost node lies, for modified dynamic boundary conditions (mDBC,
// English et al. 2021): the particle mirrored across the boundary interface into the fluid. The
// interface lies dp/2 beyond the boundary's innermost layer (where the fluid's first layer, kept at
// least dp from every boundary particle, would put it), so the particle of layer l (offsets 0, dp,
// 2dp from the face) is mirrored (2l + 1) dp along the face's normal: dp, 3dp, 5dp.
//   walls    each selected face the particle lies beyond; at edges and corners every such face,
//            so the ghost node mirrors through the edge or the corner
//   boxes    each face whose layers hold the particle (the nearer of two opposite ones), except
//            faces covered by other boundary particles (a box standing on a floor); a floating
//            box: every face, for its particles within a support of it (none deeper)
//   meshes   along the direction to the nearest point of the surface (outward), with the
//            triangle's outward normal for a particle on the surface
// Pure host geometry: no OpenCL.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <array>
#include <vector>

namespace clsph::scene {

// Per particle of `p`: the vector from it to its ghost node (zero for fluid particles, and for a
// boundary particle that none of the scene's boundaries generates: it is then interpolated at
// its own position). Boundary particles are recognised by their lattice point, so this works for
// the scene's own particles, a frame read back or a checkpoint alike.
std::vector<std::array<float, 3>> ghost_node_offsets(const Scene& scene, const Particles& p);

}  // namespace clsph::scene
