// The scene keys of open boundaries (docs/scenes.md, inlets and outlets): `inlets` and
// `outlets` read into the scene (their values are checked by scene/open_checks.cpp), and written
// back (a speed or level from a CSV file as its rows: the resolved scene needs no file).
#pragma once
#include "clsph/scene.hpp"
#include "scene/json_parse.hpp"

#include <string>

namespace clsph::scene {

// Either may be null (the key is absent). `base_dir`: what a CSV file's path is relative to.
void read_open_boundaries(const Json* inlets, const Json* outlets, const std::string& base_dir, Scene& s);
// Into doc["inlets"], doc["outlets"], only where there are some.
void write_open_boundaries(const Scene& s, Json& doc);

}  // namespace clsph::scene
