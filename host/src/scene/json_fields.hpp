// Reading one JSON object of a scene key by key, so that every error names its key path
// ("fluid[1].max: expected 3 numbers") and keys nobody asked for are reported as unknown.
#pragma once
#include "clsph/scene.hpp"
#include "scene/json_parse.hpp"

#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace clsph::scene {

// Throws SceneError "path: message" (the caller adds the file name).
[[noreturn]] void key_error(const std::string& path, const std::string& message);

// Typed readers of one value at `path`.
double read_number(const Json& v, const std::string& path);
int read_int(const Json& v, const std::string& path);
bool read_bool(const Json& v, const std::string& path);
std::string read_string(const Json& v, const std::string& path);
Vec3 read_vec3(const Json& v, const std::string& path);
// An array of 2 or 3 numbers (a height probe's [x, y] or [x, y, z]); z is 0 when absent.
Vec3 read_point(const Json& v, const std::string& path, std::size_t min_size);

// Calls each(element, "path[i]") for each element of an array at `path`.
void for_each_element(const Json& v, const std::string& path,
                      const std::function<void(const Json&, const std::string&)>& each);

class Fields {
public:
    // `path` is the object's own key path ("" for the top level, "physics", "fluid[0]"); `known`
    // lists every key the object may have. A key not in it is reported at once, before any
    // "missing required key", since a misspelt key is the likelier cause of both.
    Fields(const Json& object, std::string path, std::initializer_list<const char*> known);

    std::string path_of(const std::string& key) const;
    // The value of an optional key (nullptr when absent).
    const Json* find(const std::string& key);
    // The value of a required key: SceneError "path.key: missing required key" when absent.
    const Json& require(const std::string& key);

    double number(const std::string& key, double fallback);
    int integer(const std::string& key, int fallback);
    bool boolean(const std::string& key, bool fallback);
    std::string text(const std::string& key, const std::string& fallback);
    Vec3 vec3(const std::string& key, const Vec3& fallback);

    // A string that must be one of `options` (its JSON spelling and the value it stands for).
    template <class E>
    E choice(const std::string& key, E fallback, std::initializer_list<std::pair<const char*, E>> options) {
        const Json* v = find(key);
        if (!v) return fallback;
        const std::string s = read_string(*v, path_of(key));
        std::string known;
        for (const auto& [name, value] : options) {
            if (s == name) return value;
            known += std::string(known.empty() ? "" : ", ") + "\"" + name + "\"";
        }
        key_error(path_of(key), "unknown value \"" + s + "\" (expected one of " + known + ")");
    }

private:
    void reject_unknown() const;

    const Json& object_;
    std::string path_;
    std::vector<std::string> known_;
};

}  // namespace clsph::scene
