// Command-line overrides of a scene file: `--set physics.dp=0.01`, `--set fluid[0].max=[1,1,0.5]`,
// `--set fluid.0.max=...`. The value is JSON when it parses as JSON, otherwise a string
// (`--set physics.kernel=cubic`). Applied to the document before it becomes a Scene, so the
// overridden value meets exactly the checks a value in the file would.
#pragma once
#include "scene/json_parse.hpp"

#include <string>

namespace clsph::scene {

// Applies one `key.path=VALUE`. Missing objects on the path are created; an array index may be
// one past the end (appending). Returns the key path in the form errors name keys
// ("fluid[0].max"). Throws SceneError "source: --set ASSIGNMENT: why".
std::string apply_override(Json& doc, const std::string& assignment, const std::string& source);

// True when an error about `error_key` concerns the value at `override_key`: the same key, or
// one inside the other ("fluid[1]" and "fluid[1].max").
bool keys_related(const std::string& error_key, const std::string& override_key);

}  // namespace clsph::scene
