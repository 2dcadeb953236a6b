// Loading a scene file the way the clsph tool does: the file, then `--set KEY=VALUE` overrides.
#pragma once
#include "clsph/scene.hpp"

#include <string>
#include <vector>

namespace clsph {

// Reads the JSON scene at `path` (schema: docs/scenes.md), applies each override
// `dotted.key.path=VALUE` in order, then converts and validates the result. VALUE is read as JSON
// when it parses as JSON (0.01, [1, 2, 3], true, "text"), otherwise as a string (cubic); array
// elements are addressed as `fluid[0].max` or `fluid.0.max`. Throws SceneError naming the file,
// the key and, when an override caused it, the override.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// The same for a JSON text that is not a file (a Python dict, a string built by a host program):
// errors name `source_name`; relative mesh paths are taken from the working directory.
Scene load_scene_text(const std::string& text, const std::string& source_name,
                      const std::vector<std::string>& overrides = {});

}  // namespace clsph
