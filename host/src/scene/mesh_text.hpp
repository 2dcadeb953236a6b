// Small pieces the mesh readers share: words of a line, numbers, vertex checks.
#pragma once
#include "clsph/scene.hpp"
#include "scene/mesh_obj.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace clsph::scene::mesh_text {

inline bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

inline std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && blank(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !blank(line[i])) ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

// The whole word as a number (from_chars: no locale, no leading '+', "nan" and "inf" read).
inline bool parse_double(std::string_view s, double& out) {
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return !s.empty() && r.ec == std::errc() && r.ptr == end;
}

inline bool parse_int(std::string_view s, std::int64_t& out) {
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return !s.empty() && r.ec == std::errc() && r.ptr == end;
}

// ASCII case-insensitive equality (STL keywords are lower case, some exporters write upper).
inline bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
        if (lower(a[i]) != lower(b[i])) return false;
    }
    return true;
}

inline std::string number(double x) {
    std::ostringstream o;
    o.precision(9);
    o << x;
    return o.str();
}

// "" when the vertex is usable, otherwise why not ("is not finite (y = nan)", "has a coordinate
// beyond 1e9 (x = 1e+30)").
inline std::string vertex_problem(const Vec3& v) {
    static const char* axis[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(v[k])) return std::string("is not finite (") + axis[k] + " = " + number(v[k]) + ")";
    for (int k = 0; k < 3; ++k)
        if (std::abs(v[k]) > max_coordinate)
            return std::string("has a coordinate beyond 1e9 (") + axis[k] + " = " + number(v[k]) + ")";
    return "";
}

}  // namespace clsph::scene::mesh_text
