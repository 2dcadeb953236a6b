// The check that no two fluid blocks of a scene overlap, near-linear in the number of blocks
// (Scene::validate calls it; a scene may hold hundreds of thousands of blocks).
#pragma once
#include "clsph/scene.hpp"

#include <vector>

namespace clsph::scene {

// Throws SceneError "fluid[i]: overlaps fluid[j]" for the first overlapping pair in the user's
// order (smallest i, then smallest j < i).
void check_fluid_overlaps(const std::vector<FluidBlock>& fluids);

}  // namespace clsph::scene
