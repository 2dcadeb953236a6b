#include "scene/csv_lines.hpp"

#include "clsph/error.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <sstream>

namespace clsph::scene::csv {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

bool parse_double(std::string_view s, double& out) {
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return !s.empty() && r.ec == std::errc() && r.ptr == end;
}

std::string shown(std::string_view field) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (std::size_t i = 0; i < field.size() && i < 40; ++i) {
        const auto c = static_cast<unsigned char>(field[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (field.size() > 40) out += "...";
    return out;
}

std::string num(double x) {
    std::ostringstream o;
    o.precision(17);
    o << x;
    return o.str();
}

void fail(const std::string& key, const std::string& path, const std::string& where, const std::string& what) {
    throw SceneError(key + ": " + path + (where.empty() ? "" : ", " + where) + ": " + what);
}

Lines::Lines(const std::string& path, const std::string& key, const std::string& what_file)
    : in_(path, std::ios::binary), path_(path), key_(key) {
    if (!in_) fail("", "cannot open " + what_file + " (" + std::strerror(errno) + ")");
}

bool Lines::next(std::vector<std::string_view>& fields) {
    while (true) {
        line_.clear();
        // Bounded: a line longer than kMaxLine is refused before it is held whole.
        char c;
        bool any = false;
        while (in_.get(c)) {
            any = true;
            if (c == '\n') break;
            line_ += c;
            if (line_.size() > kMaxLine) fail("line " + std::to_string(line_no_ + 1), "longer than " + std::to_string(kMaxLine) + " characters");
        }
        if (!any) return false;
        ++line_no_;
        const std::string_view text = trim(line_);
        if (text.empty() || text[0] == '#') continue;
        fields.clear();
        std::size_t from = 0;
        while (true) {
            const std::size_t comma = text.find(',', from);
            fields.push_back(trim(text.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from)));
            if (comma == std::string_view::npos) break;
            from = comma + 1;
        }
        return true;
    }
}

}  // namespace clsph::scene::csv
