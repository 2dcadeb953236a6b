#include "scene/json_fields.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace clsph::scene {
namespace {

// Edit distance, to suggest "dp" for "dpp".
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::string expected(const std::string& what, const Json& got) { return "expected " + what + ", got " + json_type_name(got); }

}  // namespace

void key_error(const std::string& path, const std::string& message) {
    throw SceneError((path.empty() ? std::string() : path + ": ") + message);
}

double read_number(const Json& v, const std::string& path) {
    if (!v.is_number()) key_error(path, expected("a number", v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) key_error(path, "expected a finite number");
    return d;
}

int read_int(const Json& v, const std::string& path) {
    if (!v.is_number()) key_error(path, expected("an integer", v));
    const double d = v.get<double>();
    // 3.0 is accepted (a value may come through a tool that writes every number as a float).
    if (!(d == std::floor(d)) || std::abs(d) > std::numeric_limits<int>::max())
        key_error(path, "expected an integer, got " + v.dump());
    return static_cast<int>(d);
}

bool read_bool(const Json& v, const std::string& path) {
    if (!v.is_boolean()) key_error(path, expected("true or false", v));
    return v.get<bool>();
}

std::string read_string(const Json& v, const std::string& path) {
    if (!v.is_string()) key_error(path, expected("a string", v));
    return v.get<std::string>();
}

Vec3 read_point(const Json& v, const std::string& path, std::size_t min_size) {
    const std::string want = min_size == 3 ? "3 numbers" : "2 or 3 numbers";
    if (!v.is_array()) key_error(path, expected(want, v));
    if (v.size() < min_size || v.size() > 3)
        key_error(path, "expected " + want + ", got " + std::to_string(v.size()) + (v.size() == 1 ? " element" : " elements"));
    Vec3 out{0, 0, 0};
    for (std::size_t k = 0; k < v.size(); ++k) {
        if (!v[k].is_number()) key_error(path, "expected " + want + ", element " + std::to_string(k) + " is " + json_type_name(v[k]));
        out[k] = read_number(v[k], path + "[" + std::to_string(k) + "]");
    }
    return out;
}

Vec3 read_vec3(const Json& v, const std::string& path) { return read_point(v, path, 3); }

void for_each_element(const Json& v, const std::string& path,
                      const std::function<void(const Json&, const std::string&)>& each) {
    if (!v.is_array()) key_error(path, expected("an array", v));
    for (std::size_t i = 0; i < v.size(); ++i) each(v[i], path + "[" + std::to_string(i) + "]");
}

Fields::Fields(const Json& object, std::string path, std::initializer_list<const char*> known)
    : object_(object), path_(std::move(path)), known_(known.begin(), known.end()) {
    if (!object_.is_object()) key_error(path_, expected("an object", object_));
    reject_unknown();
}

std::string Fields::path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

const Json* Fields::find(const std::string& key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end())
        throw std::logic_error("clsph scene reader: key \"" + path_of(key) + "\" is missing from its known keys");
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
}

const Json& Fields::require(const std::string& key) {
    const Json* v = find(key);
    if (!v) key_error(path_of(key), "missing required key");
    return *v;
}

double Fields::number(const std::string& key, double fallback) {
    const Json* v = find(key);
    return v ? read_number(*v, path_of(key)) : fallback;
}

int Fields::integer(const std::string& key, int fallback) {
    const Json* v = find(key);
    return v ? read_int(*v, path_of(key)) : fallback;
}

bool Fields::boolean(const std::string& key, bool fallback) {
    const Json* v = find(key);
    return v ? read_bool(*v, path_of(key)) : fallback;
}

std::string Fields::text(const std::string& key, const std::string& fallback) {
    const Json* v = find(key);
    return v ? read_string(*v, path_of(key)) : fallback;
}

Vec3 Fields::vec3(const std::string& key, const Vec3& fallback) {
    const Json* v = find(key);
    return v ? read_vec3(*v, path_of(key)) : fallback;
}

void Fields::reject_unknown() const {
    for (const auto& item : object_.items()) {
        const std::string& key = item.key();
        if (std::find(known_.begin(), known_.end(), key) != known_.end()) continue;
        std::string nearest;
        std::size_t best = 3;  // suggest only keys at most two edits away
        for (const auto& k : known_) {
            const std::size_t d = edit_distance(key, k);
            if (d < best) best = d, nearest = k;
        }
        std::string hint;
        if (!nearest.empty()) {
            hint = " (did you mean \"" + nearest + "\"?)";
        } else {
            for (const auto& k : known_) hint += (hint.empty() ? " (known keys: " : ", ") + k;
            if (!hint.empty()) hint += ")";
        }
        key_error(path_of(key), "unknown key" + hint);
    }
}

}  // namespace clsph::scene
