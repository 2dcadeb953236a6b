// The scene keys of open boundaries (docs/scenes.md, inlets and outlets): `inlets` and
// `outlets` read into the scene (their values are checked by scene/open_boundaries.cpp).
#pragma once
#include "clsph/scene.hpp"
#include "scene/json_parse.hpp"

namespace clsph::scene {

// Either may be null (the key is absent).
void read_open_boundaries(const Json* inlets, const Json* outlets, Scene& s);

}  // namespace clsph::scene
