// Turning the text of a scene file into a JSON document, with errors a user can act on: the file
// name, line and column of a syntax error, duplicate keys, empty or binary files.
#pragma once
#include <cstddef>
#include <nlohmann/json.hpp>

#include <string>

namespace clsph::scene {

// Key order is kept so that a scene written back reads in the order its author wrote it.
using Json = nlohmann::ordered_json;

// Parses `text` (the contents of `source`, a file name used in messages) into a JSON object.
// Throws SceneError "source: line L, column C: ..." for syntax errors, and names the key path of a
// duplicate key (nlohmann would silently keep the last one).
Json parse_scene_text(const std::string& text, const std::string& source);

// The contents of a file; SceneError "path: cannot read: <OS error>" when it cannot be read.
// Scene files are text of at most this size (the largest shipped scene is a few KiB).
constexpr std::size_t max_scene_bytes = std::size_t{64} << 20;
std::string read_text_file(const std::string& path);

// The name of a JSON value's type as a user reads it ("a number", "an array", ...).
std::string json_type_name(const Json& value);

}  // namespace clsph::scene
