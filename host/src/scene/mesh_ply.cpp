// PLY meshes: ASCII, binary_little_endian and binary_big_endian (format 1.0).
//
// A reader of our own for the reasons in mesh_stl.cpp (Assimp is too large a dependency for two
// simple formats and cannot name the element at fault; RPly and tinyply are not in Debian).
//
// The header ("ply", "format ...", then "element NAME COUNT" each followed by its "property TYPE
// NAME" or "property list COUNTTYPE ITEMTYPE NAME" lines, "comment"/"obj_info" lines anywhere,
// "end_header") declares every element; the body holds them in that order. We keep the `vertex`
// element's x, y, z (any scalar type) and the `face` element's vertex_indices (or vertex_index)
// list of integer indices, 0-based; faces of more than 3 vertices are fanned around the first.
// Every other element and property is skipped by its declared type. Elements are numbered from
// 0 in errors, as faces index vertices. Before anything is allocated, the least number of bytes
// the declared counts need is checked against the file's size.
#include "clsph/error.hpp"
#include "scene/mesh_formats.hpp"
#include "scene/mesh_text.hpp"

#include <cstring>

namespace clsph::scene {
namespace {

using namespace mesh_text;

enum class Kind { int_signed, int_unsigned, real };
struct Type {
    Kind kind = Kind::real;
    int bytes = 0;
};

bool type_of(std::string_view name, Type& t) {
    struct Named {
        const char* a;
        const char* b;
        Type t;
    };
    static const Named types[] = {
        {"char", "int8", {Kind::int_signed, 1}},      {"uchar", "uint8", {Kind::int_unsigned, 1}},
        {"short", "int16", {Kind::int_signed, 2}},    {"ushort", "uint16", {Kind::int_unsigned, 2}},
        {"int", "int32", {Kind::int_signed, 4}},      {"uint", "uint32", {Kind::int_unsigned, 4}},
        {"float", "float32", {Kind::real, 4}},        {"double", "float64", {Kind::real, 8}},
    };
    for (const auto& n : types)
        if (name == n.a || name == n.b) return t = n.t, true;
    return false;
}

struct Property {
    std::string name;
    bool list = false;
    Type count, item;  // count: lists only
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Format { ascii, little, big };

// One value of the body, as a double (reals) or an integer (integer types).
struct Value {
    double real = 0;
    std::int64_t integer = 0;
};

class Body {
public:
    Body(const std::string& path, std::string_view bytes, Format format) : path_(path), b_(bytes), format_(format) {}

    [[noreturn]] void fail(const std::string& what) const {
        std::string where;
        if (format_ == Format::ascii) where = "line " + std::to_string(line_) + ": ";
        throw SceneError(path_ + ": " + where + what);
    }

    std::size_t left() const { return b_.size() - at_; }

    // A value of type t; `what` names it for errors ("vertex 3", "face 7").
    Value read(const Type& t, const std::string& what) {
        Value v;
        if (format_ == Format::ascii) {
            const std::string_view word = next_word();
            if (word.empty()) fail("the file ends inside " + what + " (truncated, or a count in the header is too large)");
            if (t.kind == Kind::real) {
                if (!parse_double(word, v.real)) fail(what + ": '" + std::string(word) + "' is not a number");
            } else {
                if (!parse_int(word, v.integer)) fail(what + ": '" + std::string(word) + "' is not an integer");
                v.real = static_cast<double>(v.integer);
            }
            return v;
        }
        if (left() < static_cast<std::size_t>(t.bytes))
            fail("the file ends inside " + what + " (truncated, or a count in the header is too large)");
        std::uint64_t bits = 0;
        const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + at_);
        for (int i = 0; i < t.bytes; ++i) {
            const int shift = 8 * (format_ == Format::little ? i : t.bytes - 1 - i);
            bits |= std::uint64_t{p[i]} << shift;
        }
        at_ += static_cast<std::size_t>(t.bytes);
        if (t.kind == Kind::real) {
            if (t.bytes == 4) {
                float f;
                const auto u = static_cast<std::uint32_t>(bits);
                std::memcpy(&f, &u, sizeof f);
                v.real = f;
            } else {
                std::memcpy(&v.real, &bits, sizeof v.real);
            }
            return v;
        }
        if (t.kind == Kind::int_signed && t.bytes < 8 && (bits >> (8 * t.bytes - 1)) & 1)
            bits |= ~std::uint64_t{0} << (8 * t.bytes);  // sign extension
        v.integer = static_cast<std::int64_t>(bits);
        v.real = static_cast<double>(v.integer);
        return v;
    }

    // Whatever follows the last element: nothing but white space (ASCII) or nothing (binary).
    void expect_end() {
        if (format_ == Format::ascii) {
            if (!next_word().empty()) fail("the file goes on after the last element the header declares (a count in the header is too small?)");
        } else if (left() > 0) {
            fail(std::to_string(left()) + " bytes follow the last element the header declares (a count in the header is too small?)");
        }
    }

private:
    std::string_view next_word() {
        while (at_ < b_.size() && (blank(b_[at_]) || b_[at_] == '\n')) {
            if (b_[at_] == '\n') ++line_;
            ++at_;
        }
        const std::size_t start = at_;
        while (at_ < b_.size() && !blank(b_[at_]) && b_[at_] != '\n') ++at_;
        return b_.substr(start, at_ - start);
    }

    std::string path_;
    std::string_view b_;
    Format format_;
    std::size_t at_ = 0;

public:
    std::size_t line_ = 1;
};

struct Header {
    Format format = Format::ascii;
    std::vector<Element> elements;
    std::size_t body = 0;   // offset of the first byte after "end_header\n"
    std::size_t lines = 0;  // lines in the header
};

Header read_header(const std::string& path, std::string_view b) {
    if (!(b.substr(0, 4) == "ply\n" || b.substr(0, 5) == "ply\r\n")) {
        const std::string hint = iequals(b.substr(0, 5), "solid") || b.size() >= 84 ? " (an STL file? name it .stl)" : "";
        throw SceneError(path + ": not a PLY file: it does not start with the line 'ply'" + hint);
    }
    Header h;
    std::size_t at = 0;
    bool format_seen = false, ended = false;
    while (at < b.size() && !ended) {
        const std::size_t eol = b.find('\n', at);
        if (eol == std::string_view::npos) break;
        const std::string_view line = b.substr(at, eol - at);
        at = eol + 1;
        ++h.lines;
        const auto fail = [&](const std::string& what) {
            throw SceneError(path + ": header line " + std::to_string(h.lines) + ": " + what);
        };
        const auto w = split_words(line);
        if (h.lines == 1 || w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format") {
            if (w.size() != 3 || w[2] != "1.0") fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
            if (w[1] == "ascii") h.format = Format::ascii;
            else if (w[1] == "binary_little_endian") h.format = Format::little;
            else if (w[1] == "binary_big_endian") h.format = Format::big;
            else fail("'" + std::string(w[1]) + "' is not a PLY format (ascii, binary_little_endian, binary_big_endian)");
            format_seen = true;
        } else if (w[0] == "element") {
            std::int64_t count = 0;
            if (w.size() != 3 || !parse_int(w[2], count) || count < 0) fail("expected 'element NAME COUNT'");
            h.elements.push_back({std::string(w[1]), static_cast<std::uint64_t>(count), {}});
        } else if (w[0] == "property") {
            if (h.elements.empty()) fail("a property before any element");
            Property p;
            if (w.size() == 5 && w[1] == "list") {
                p.list = true;
                if (!type_of(w[2], p.count) || p.count.kind == Kind::real) fail("a list's count type must be an integer type");
                if (!type_of(w[3], p.item)) fail("'" + std::string(w[3]) + "' is not a PLY type");
                p.name = std::string(w[4]);
            } else if (w.size() == 3) {
                if (!type_of(w[1], p.item)) fail("'" + std::string(w[1]) + "' is not a PLY type");
                p.name = std::string(w[2]);
            } else {
                fail("expected 'property TYPE NAME' or 'property list COUNTTYPE ITEMTYPE NAME'");
            }
            h.elements.back().properties.push_back(p);
        } else if (w[0] == "end_header") {
            ended = true;
        } else {
            fail("'" + std::string(w[0]) + "' is not a PLY header keyword");
        }
    }
    if (!ended) throw SceneError(path + ": the PLY header has no 'end_header' line (truncated?)");
    if (!format_seen) throw SceneError(path + ": the PLY header has no 'format' line");
    h.body = at;
    return h;
}

// The least number of bytes the declared elements take in the body, checked against what is there.
void check_counts(const std::string& path, const Header& h, std::size_t body_bytes) {
    double least = 0;  // double: counts up to 2^63 times sizes cannot overflow it
    for (const auto& e : h.elements) {
        double per = 0;
        for (const auto& p : e.properties)
            per += h.format == Format::ascii ? 2.0 : (p.list ? p.count.bytes : p.item.bytes);
        least += static_cast<double>(e.count) * per;
    }
    if (least > static_cast<double>(body_bytes) + 1.0) {
        std::string declared;
        for (const auto& e : h.elements)
            declared += (declared.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name;
        throw SceneError(path + ": the header declares " + declared + ", at least " + number(least) +
                         " bytes, but only " + std::to_string(body_bytes) + " follow it (truncated, or a wrong count)");
    }
}

}  // namespace

TriangleMesh read_ply(const std::string& path) {
    const std::string bytes = read_mesh_bytes(path);
    const std::string_view b(bytes);
    const Header h = read_header(path, b);
    check_counts(path, h, b.size() - h.body);

    const Element* vertex = nullptr;
    const Element* face = nullptr;
    int xyz[3] = {-1, -1, -1};
    int indices = -1;
    for (const auto& e : h.elements) {
        if (e.name == "vertex" && !vertex) {
            vertex = &e;
            for (std::size_t i = 0; i < e.properties.size(); ++i)
                for (int k = 0; k < 3; ++k)
                    if (e.properties[i].name == std::string(1, static_cast<char>('x' + k)) && !e.properties[i].list) xyz[k] = static_cast<int>(i);
        } else if (e.name == "face" && !face) {
            face = &e;
            for (std::size_t i = 0; i < e.properties.size(); ++i)
                if ((e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index") && indices < 0) {
                    if (!e.properties[i].list || e.properties[i].item.kind == Kind::real)
                        throw SceneError(path + ": the face element's " + e.properties[i].name + " must be a list of integers");
                    indices = static_cast<int>(i);
                }
        }
    }
    if (!vertex) throw SceneError(path + ": the PLY header declares no 'vertex' element");
    for (int k = 0; k < 3; ++k)
        if (xyz[k] < 0) throw SceneError(path + ": the vertex element has no property '" + std::string(1, static_cast<char>('x' + k)) + "'");
    if (!face || face->count == 0) throw SceneError(path + ": the mesh has no faces (the PLY header declares no 'face' element)");
    if (indices < 0) throw SceneError(path + ": the face element has no 'vertex_indices' list");
    if (vertex->count > 0xffffffffu) throw SceneError(path + ": more than 2^32 vertices");

    TriangleMesh mesh;
    mesh.vertices.reserve(vertex->count);  // counts were checked against the file's size
    mesh.triangles.reserve(face->count);
    Body body(path, b.substr(h.body), h.format);
    body.line_ = h.lines + 1;
    for (const auto& e : h.elements) {
        if (e.properties.empty()) continue;  // nothing in the body, whatever its count
        for (std::uint64_t n = 0; n < e.count; ++n) {
            const std::string what = e.name + " " + std::to_string(n);
            Vec3 v{};
            std::int64_t first = -1, previous = -1;
            for (std::size_t i = 0; i < e.properties.size(); ++i) {
                const Property& p = e.properties[i];
                if (!p.list) {
                    const Value x = body.read(p.item, what);
                    if (&e == vertex)
                        for (int k = 0; k < 3; ++k)
                            if (xyz[k] == static_cast<int>(i)) v[k] = x.real;
                    continue;
                }
                const std::int64_t count = body.read(p.count, what).integer;
                const bool ours = &e == face && static_cast<int>(i) == indices;
                if (count < 0) body.fail(what + ": a list of " + std::to_string(count) + " items");
                if (ours && count < 3) body.fail(what + " has " + std::to_string(count) + " vertices (a face needs at least 3)");
                const std::size_t least = h.format == Format::ascii ? 2 : static_cast<std::size_t>(p.item.bytes);
                if (static_cast<std::uint64_t>(count) > body.left() / least + 1)
                    body.fail(what + ": a list of " + std::to_string(count) + " items, more than the rest of the file holds (truncated, or a wrong count)");
                for (std::int64_t j = 0; j < count; ++j) {
                    const Value x = body.read(p.item, what);
                    if (!ours) continue;
                    const std::int64_t index = x.integer;
                    if (index < 0 || static_cast<std::uint64_t>(index) >= vertex->count)
                        body.fail(what + ": vertex index " + std::to_string(index) + " is out of range (the file has " +
                                  std::to_string(vertex->count) + " vertices)");
                    if (j == 0) {
                        first = index;
                    } else if (j >= 2 && first != previous && previous != index && first != index) {
                        mesh.triangles.push_back({static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(previous),
                                                  static_cast<std::uint32_t>(index)});
                    }
                    previous = index;
                }
            }
            if (&e == vertex) {
                if (const std::string why = vertex_problem(v); !why.empty()) body.fail(what + " " + why);
                mesh.vertices.push_back(v);
            }
        }
    }
    body.expect_end();
    if (mesh.triangles.empty())
        throw SceneError(path + ": the mesh has no faces (no face with 3 or more distinct vertices)");
    return mesh;
}

}  // namespace clsph::scene
