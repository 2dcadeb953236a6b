// The numeric CSV files a scene names (a solid's motion, an inlet's speed, an outlet's level),
// read with the same care for hostile input: lines bounded before they are held whole, blank lines
// and lines starting with '#' skipped, numbers parsed whole by std::from_chars (no locale, no
// trailing text), and every error a SceneError "key: path, line L...: what".
#pragma once
#include <cstddef>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace clsph::scene::csv {

constexpr std::size_t kMaxLine = 4096;
constexpr double kMaxValue = 1e9;

std::string_view trim(std::string_view s);
// The whole of `s` as a number (an optional leading '+'); false for anything else.
bool parse_double(std::string_view s, double& out);
// A field as a message quotes it: bytes outside printable ASCII as \xNN (a NUL would end the
// message's C string), at most 40 characters of it.
std::string shown(std::string_view field);
// A number as the messages write it (17 digits: the value read, not a rounding of it).
std::string num(double x);

// A file's first row is a header when its first field starts with a letter.
inline bool is_header(const std::vector<std::string_view>& fields) {
    const char f = fields.empty() || fields[0].empty() ? ' ' : fields[0][0];
    return (f >= 'a' && f <= 'z') || (f >= 'A' && f <= 'Z');
}

// Throws SceneError "key: path[, where]: what".
[[noreturn]] void fail(const std::string& key, const std::string& path, const std::string& where, const std::string& what);

// The rows of a file one by one: each line that is not blank or a comment, split at commas into
// trimmed fields (views into the line, valid until the next call).
class Lines {
public:
    // `what_file` names the file in the message when it cannot be opened ("the motion file").
    Lines(const std::string& path, const std::string& key, const std::string& what_file);
    bool next(std::vector<std::string_view>& fields);
    std::size_t line() const { return line_no_; }
    std::string at() const { return "line " + std::to_string(line_no_); }
    [[noreturn]] void fail(const std::string& where, const std::string& what) const { csv::fail(key_, path_, where, what); }

private:
    std::ifstream in_;
    std::string path_, key_, line_;
    std::size_t line_no_ = 0;
};

}  // namespace clsph::scene::csv
