#include "scene/json_parse.hpp"

#include "clsph/error.hpp"
#include "io/file.hpp"

#include <cerrno>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace clsph::scene {
namespace {

struct Position {
    std::size_t line = 1, column = 1;
};

// 1-based line and column of the byte at `offset` (columns count bytes, as editors showing UTF-8
// mostly agree on for the ASCII that JSON syntax is made of).
Position position_of(const std::string& text, std::size_t offset) {
    Position p;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++p.line;
            p.column = 1;
        } else {
            ++p.column;
        }
    }
    return p;
}

std::string at(const std::string& source, Position p) {
    return source + ": line " + std::to_string(p.line) + ", column " + std::to_string(p.column) + ": ";
}

// A message may quote bytes of a binary file: keep it printable and short.
std::string printable(const std::string& s, std::size_t limit = 160) {
    std::string out;
    for (unsigned char c : s) {
        if (out.size() >= limit) {
            out += "...";
            break;
        }
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            static const char* hex = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

// nlohmann's message is "[json.exception.parse_error.101] parse error at line 1, column 2: what";
// keep "what", since we give the position ourselves.
std::string parse_error_detail(const std::string& what) {
    const auto pe = what.find("parse error");
    const auto colon = what.find(": ", pe == std::string::npos ? 0 : pe);
    return printable(colon == std::string::npos ? what : what.substr(colon + 2));
}

// Other nlohmann errors ("[json.exception.out_of_range.406] number overflow parsing '1e999'")
// without the bracketed prefix.
std::string other_error_detail(const std::string& what) {
    const auto close = what.find("] ");
    return printable(what.rfind("[json.exception", 0) == 0 && close != std::string::npos ? what.substr(close + 2) : what);
}

// The text quoted in "... parsing 'TOKEN'" ("" if none).
std::string quoted_token(const std::string& what, const std::string& lead) {
    const auto begin = what.find(lead);
    if (begin == std::string::npos) return "";
    const auto from = begin + lead.size();
    const auto end = what.rfind('\'');
    return end == std::string::npos || end < from ? "" : what.substr(from, end - from);
}

bool structural(char c) { return c == '{' || c == '}' || c == '[' || c == ']' || c == ',' || c == ':'; }

// nlohmann reports the offset of the last byte it read, the end of the offending token; users look
// for where the token starts: back to the opening quote of a string, or over a number or word.
std::size_t token_start(const std::string& text, std::size_t byte) {
    if (text.empty()) return 0;
    const std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size() - 1);
    const char last = text[end];
    if (last == '"') {
        for (std::size_t i = end; i-- > 0;)
            if (text[i] == '"' && (i == 0 || text[i - 1] != '\\')) return i;
        return end;
    }
    if (structural(last) || std::isspace(static_cast<unsigned char>(last))) return end;
    std::size_t i = end;
    while (i > 0 && !structural(text[i - 1]) && text[i - 1] != '"' && !std::isspace(static_cast<unsigned char>(text[i - 1])))
        --i;
    return i;
}

// Tracks where the parser is (object keys, array indices) so that a duplicate key can be named by
// its key path; nlohmann itself keeps the last value of a duplicate key without a word.
// A SAX pass over the text that only looks for a key repeated within one object (which a DOM
// parse would silently resolve to the last value) and names its key path. SAX rather than
// nlohmann's parse callback, whose end of each object rescans the enclosing array: quadratic in a
// scene of many fluid blocks.
class DuplicateKeyCheck : public nlohmann::json_sax<Json> {
public:
    explicit DuplicateKeyCheck(std::string source) : source_(std::move(source)) {}

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        frames_.push_back({true, {}, {}, 0});
        return true;
    }
    bool key(string_t& k) override {
        Frame& f = frames_.back();
        f.key = k;
        if (!f.keys.insert(f.key).second)
            throw SceneError(source_ + ": " + path() + ": duplicate key (each key may appear once)");
        return true;
    }
    bool end_object() override { return end(); }
    bool start_array(std::size_t) override {
        frames_.push_back({false, {}, {}, 0});
        return true;
    }
    bool end_array() override { return end(); }
    // The DOM parse before this one has reported syntax errors already.
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

private:
    struct Frame {
        bool object;
        std::set<std::string> keys;
        std::string key;
        std::size_t index;
    };

    void next_element() {
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    }
    bool value() {
        next_element();
        return true;
    }
    bool end() {
        frames_.pop_back();
        next_element();
        return true;
    }

    std::string path() const {
        std::string p;
        for (const Frame& f : frames_) {
            if (f.object)
                p += (p.empty() ? "" : ".") + f.key;
            else
                p += "[" + std::to_string(f.index) + "]";
        }
        return p;
    }

    std::string source_;
    std::vector<Frame> frames_;
};

}  // namespace

std::string json_type_name(const Json& v) {
    switch (v.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::object: return "an object";
        case Json::value_t::array: return "an array";
        case Json::value_t::string: return "a string";
        case Json::value_t::boolean: return "a boolean";
        case Json::value_t::number_integer:
        case Json::value_t::number_unsigned:
        case Json::value_t::number_float: return "a number";
        default: return "an unsupported value";
    }
}

std::string read_text_file(const std::string& path) {
    // Only regular files of a sane size: a scene path that is /dev/zero or a FIFO is refused
    // before a byte is read, rather than read until memory runs out.
    if (const std::string why = io::file_problem(path, max_scene_bytes); !why.empty())
        throw SceneError(path + ": cannot read: " + why);
    try {
        return io::read_file(path, max_scene_bytes);
    } catch (const Error& e) {
        const std::string what = e.what(), lead = "cannot read " + path + ": ";
        throw SceneError(path + ": cannot read: " + (what.rfind(lead, 0) == 0 ? what.substr(lead.size()) : what));
    }
}

Json parse_scene_text(const std::string& text, const std::string& source) {
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw SceneError(source + ": the file is empty (a scene is a JSON object; see docs/scenes.md)");
    // Control bytes other than white space cannot occur in JSON text: say "binary" rather than
    // quoting a parser's complaint about some byte in the middle of garbage.
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
            throw SceneError(at(source, position_of(text, i)) + "byte " + printable(std::string(1, text[i])) +
                             ": this is not a text file (a scene is a JSON object; see docs/scenes.md)");
    }
    Json doc;
    try {
        doc = Json::parse(text);
        DuplicateKeyCheck duplicates(source);
        Json::sax_parse(text, &duplicates);
    } catch (const nlohmann::json::parse_error& e) {
        throw SceneError(at(source, position_of(text, token_start(text, e.byte))) + parse_error_detail(e.what()));
    } catch (const nlohmann::json::exception& e) {
        // A number too large for a double: no position from nlohmann, but it quotes the number.
        const std::string token = quoted_token(e.what(), "parsing '");
        const auto where = token.empty() ? std::string::npos : text.find(token);
        throw SceneError((where == std::string::npos ? source + ": " : at(source, position_of(text, where))) +
                         other_error_detail(e.what()));
    }
    if (!doc.is_object())
        throw SceneError(source + ": expected a JSON object at the top level, got " + json_type_name(doc));
    return doc;
}

}  // namespace clsph::scene
