// A scene document (parsed JSON) to a Scene and back. Shared by Scene::from_file /
// from_json_text / to_json and load_scene (which edits the document with --set overrides first).
#pragma once
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "scene/json_parse.hpp"

#include <string>
#include <vector>

namespace clsph::scene {

struct DocumentOrigin {
    std::string default_name = "scene";  // the scene's name when the document gives none
    std::string base_dir;                // relative mesh paths are resolved against it ("": cwd)
};

// Converts and validates. Errors are SceneError "key.path: message", without the file name: the
// caller knows where the document came from and prefixes it (with_source).
Scene scene_from_document(const Json& doc, const DocumentOrigin& origin);

// Every key with its value, defaults included, in the order docs/scenes.md lists them.
Json scene_to_document(const Scene& scene);

// load_scene on the text of the file at `path` (already read): what the fuzzer drives.
Scene load_scene_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides);
// The same with the origin relative mesh paths are resolved against given.
Scene load_scene_document(const std::string& text, const std::string& path, const DocumentOrigin& origin,
                          const std::vector<std::string>& overrides);

// The scene's name for a file ("scenes/dam_break.json" -> "dam_break").
std::string scene_name_for(const std::string& path);

// Runs `f`; a SceneError "key: message" from it becomes "source: key: message".
template <class F>
auto with_source(const std::string& source, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const SceneError& e) {
        throw SceneError(source + ": " + e.what());
    }
}

}  // namespace clsph::scene
