#include "scene/json_overrides.hpp"

#include "clsph/error.hpp"

#include <cctype>
#include <optional>
#include <vector>

namespace clsph::scene {
namespace {

// One step of a key path: an object key, or an array index. "0" in `fluid.0.max` may be either,
// depending on what it meets: an index into an array, a key of an object.
struct Step {
    std::string key;
    std::optional<std::size_t> index;
    bool bracket = false;  // written as [n]: only ever an index
};

bool all_digits(const std::string& s) {
    if (s.empty() || s.size() > 9) return false;
    for (char c : s)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    return true;
}

class OverrideError {
public:
    OverrideError(std::string source, std::string assignment)
        : prefix_(std::move(source) + ": --set " + std::move(assignment) + ": ") {}
    [[noreturn]] void operator()(const std::string& why) const { throw SceneError(prefix_ + why); }

private:
    std::string prefix_;
};

std::vector<Step> parse_key(const std::string& key, const OverrideError& fail) {
    std::vector<Step> steps;
    std::size_t i = 0;
    while (i < key.size()) {
        if (key[i] == '[') {
            const auto close = key.find(']', i);
            if (close == std::string::npos) fail("unclosed '[' in the key");
            const std::string digits = key.substr(i + 1, close - i - 1);
            if (!all_digits(digits)) fail("'[" + digits + "]' is not an array index");
            steps.push_back({digits, std::stoul(digits), true});
            i = close + 1;
            if (i < key.size() && key[i] == '.') {
                ++i;
                if (i == key.size()) fail("the key ends with '.'");
            }
            continue;
        }
        const auto end = key.find_first_of(".[", i);
        const std::string name = key.substr(i, end == std::string::npos ? std::string::npos : end - i);
        if (name.empty()) fail("empty key between dots");
        steps.push_back({name, all_digits(name) ? std::optional<std::size_t>(std::stoul(name)) : std::nullopt, false});
        i = end == std::string::npos ? key.size() : end;
        if (i < key.size() && key[i] == '.') {
            ++i;
            if (i == key.size()) fail("the key ends with '.'");
        }
    }
    if (steps.empty()) fail("empty key (expected KEY=VALUE, e.g. physics.dp=0.01)");
    return steps;
}

}  // namespace

bool keys_related(const std::string& error_key, const std::string& override_key) {
    auto within = [](const std::string& inner, const std::string& outer) {
        return inner.size() > outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
               (inner[outer.size()] == '.' || inner[outer.size()] == '[');
    };
    return error_key == override_key || within(error_key, override_key) || within(override_key, error_key);
}

std::string apply_override(Json& doc, const std::string& assignment, const std::string& source) {
    const OverrideError fail(source, assignment);
    const auto eq = assignment.find('=');
    if (eq == std::string::npos) fail("expected KEY=VALUE (e.g. physics.dp=0.01)");
    const std::vector<Step> steps = parse_key(assignment.substr(0, eq), fail);
    const std::string text = assignment.substr(eq + 1);
    Json value = Json::parse(text, nullptr, false);  // no exceptions: a failure gives "discarded"
    if (value.is_discarded()) value = text;

    Json* node = &doc;
    std::string path;
    for (std::size_t s = 0; s < steps.size(); ++s) {
        const Step& step = steps[s];
        const bool last = s + 1 == steps.size();
        // What to create when the next step is missing: an array when it is an index.
        const bool next_is_index = !last && steps[s + 1].index.has_value();
        if (node->is_object() && !step.bracket) {
            path += (path.empty() ? "" : ".") + step.key;
            if (last) {
                (*node)[step.key] = value;
                return path;
            }
            if (!node->contains(step.key)) (*node)[step.key] = next_is_index ? Json::array() : Json::object();
            node = &(*node)[step.key];
        } else if (node->is_array() && step.index) {
            const std::size_t i = *step.index;
            path += "[" + std::to_string(i) + "]";
            if (i > node->size())
                fail(path + ": index out of range (the array has " + std::to_string(node->size()) + " elements)");
            if (i == node->size()) node->push_back(next_is_index ? Json::array() : Json::object());
            if (last) {
                (*node)[i] = value;
                return path;
            }
            node = &(*node)[i];
        } else {
            const std::string here = path.empty() ? "the scene" : path;
            fail(here + " is " + json_type_name(*node) + ", which has no " +
                 (step.index ? "element " : "key ") + (step.bracket ? "[" + step.key + "]" : "\"" + step.key + "\""));
        }
    }
    return path;  // not reached: the last step returns
}

}  // namespace clsph::scene
