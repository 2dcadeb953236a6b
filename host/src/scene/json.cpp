// Scene files: Scene::from_file / from_json_text / to_json and load_scene (with --set overrides).
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "clsph/scene_io.hpp"
#include "scene/json_overrides.hpp"
#include "scene/json_parse.hpp"
#include "scene/json_scene.hpp"

#include <filesystem>

namespace clsph {
namespace {

scene::DocumentOrigin origin_of_file(const std::string& path) {
    return {scene::scene_name_for(path), std::filesystem::path(path).parent_path().string()};
}

}  // namespace

Scene Scene::from_file(const std::string& path) { return load_scene(path, {}); }

Scene Scene::from_json_text(const std::string& text, const std::string& source_name) {
    const scene::Json doc = scene::parse_scene_text(text, source_name);
    // Relative mesh paths in a text without a file are taken from the working directory.
    const scene::DocumentOrigin origin{scene::scene_name_for(source_name), ""};
    return scene::with_source(source_name, [&] { return scene::scene_from_document(doc, origin); });
}

std::string Scene::to_json() const { return scene::scene_to_document(*this).dump(2) + "\n"; }

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
    return scene::load_scene_text(scene::read_text_file(path), path, overrides);
}

Scene scene::load_scene_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides) {
    return load_scene_document(text, path, origin_of_file(path), overrides);
}

Scene load_scene_text(const std::string& text, const std::string& source_name, const std::vector<std::string>& overrides) {
    // Relative mesh paths in a text without a file are taken from the working directory.
    return scene::load_scene_document(text, source_name, {scene::scene_name_for(source_name), ""}, overrides);
}

Scene scene::load_scene_document(const std::string& text, const std::string& path, const DocumentOrigin& origin,
                                 const std::vector<std::string>& overrides) {
    scene::Json doc = scene::parse_scene_text(text, path);
    std::vector<std::string> keys;
    for (const auto& o : overrides) keys.push_back(scene::apply_override(doc, o, path));
    try {
        return scene::scene_from_document(doc, origin);
    } catch (const SceneError& e) {
        // "key: message"; when an override set that key (or one around it), say so.
        std::string message = e.what();
        const std::string key = message.substr(0, message.find(": "));
        for (std::size_t i = overrides.size(); i-- > 0;)
            if (scene::keys_related(key, keys[i])) {
                message += " (set by --set " + overrides[i] + ")";
                break;
            }
        throw SceneError(path + ": " + message);
    }
}

}  // namespace clsph
