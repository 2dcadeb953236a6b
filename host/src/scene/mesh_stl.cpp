// STL meshes, binary and ASCII.
//
// Why a reader of our own: Debian's mesh readers are libassimp-dev (Assimp: some 40 formats, a
// 10 MB library with its own dependencies, and it post-processes what it reads, so an error
// could not name the triangle at fault) and libadmesh-dev (ADMesh: STL only, and meant for
// repairing meshes); RPly and tinyply are not packaged. STL is 50 bytes a triangle, or seven
// keywords a triangle in ASCII: a bounded reader is shorter than the glue any of them would need.
//
// Binary STL (little-endian): an 80-byte header, the triangle count n (uint32), then per triangle
// a normal and three vertices (12 float32) and a 16-bit attribute word, 84 + 50 n bytes in all.
// ASCII: "solid name", then per triangle "facet normal nx ny nz", "outer loop", three "vertex x y
// z", "endloop", "endfacet", and "endsolid name" (several solids may follow each other). Normals
// are ignored in both: inside and outside come from the closed surface itself.
#include "clsph/error.hpp"
#include "scene/mesh_formats.hpp"
#include "scene/mesh_text.hpp"

#include <cstring>

namespace clsph::scene {
namespace {

using namespace mesh_text;

std::uint32_t le32(const char* p) {
    const auto* b = reinterpret_cast<const unsigned char*>(p);
    return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
}

float le_float(const char* p) {
    const std::uint32_t bits = le32(p);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

bool starts_with_solid(std::string_view bytes) {
    std::size_t i = 0;
    while (i < bytes.size() && (blank(bytes[i]) || bytes[i] == '\n')) ++i;
    return iequals(bytes.substr(i, 5), "solid");
}

void add_vertex(TriangleMesh& mesh, const std::string& path, std::uint64_t triangle, int corner, const Vec3& v,
                const std::string& where = "") {
    if (const std::string why = vertex_problem(v); !why.empty())
        throw SceneError(path + ": triangle " + std::to_string(triangle) + where + ": vertex " + std::to_string(corner) + " " + why);
    mesh.vertices.push_back(v);
}

TriangleMesh read_binary(const std::string& path, std::string_view bytes, std::uint64_t n) {
    TriangleMesh mesh;
    mesh.vertices.reserve(3 * n);  // n was checked against the file's size
    mesh.triangles.reserve(n);
    for (std::uint64_t t = 0; t < n; ++t) {
        const char* p = bytes.data() + 84 + 50 * t + 12;  // past the normal
        for (int c = 0; c < 3; ++c) {
            Vec3 v{};
            for (int k = 0; k < 3; ++k) v[k] = le_float(p + 12 * c + 4 * k);
            add_vertex(mesh, path, t + 1, c + 1, v);
        }
        const auto i = static_cast<std::uint32_t>(3 * t);
        mesh.triangles.push_back({i, i + 1, i + 2});
    }
    return mesh;
}

struct AsciiStl {
    std::string path;
    bool looks_binary = false;  // the file starts with "solid" but holds control bytes
    std::string binary_note;
    TriangleMesh mesh;

    [[noreturn]] void fail(std::size_t line, const std::string& what) const {
        throw SceneError(path + ": line " + std::to_string(line) + ": " + what + (looks_binary ? binary_note : ""));
    }

    void read(std::string_view text) {
        enum class Expect { solid, facet, outer, vertex, endloop, endfacet } expect = Expect::solid;
        int corner = 0;
        std::size_t line_no = 0, solids = 0;
        std::uint64_t triangle = 0;
        Vec3 corners[3]{};
        while (!text.empty()) {
            const std::size_t eol = text.find('\n');
            const std::string_view line = text.substr(0, eol);
            text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
            ++line_no;
            const auto w = split_words(line);
            if (w.empty()) continue;
            const auto is = [&](const char* word) { return iequals(w[0], word); };
            switch (expect) {
                case Expect::solid:
                    if (!is("solid")) fail(line_no, "expected 'solid'");
                    expect = Expect::facet;  // the rest of the line is the solid's name
                    break;
                case Expect::facet:
                    if (is("endsolid")) {
                        ++solids;
                        expect = Expect::solid;
                        break;
                    }
                    if (!is("facet") || w.size() != 5 || !iequals(w[1], "normal"))
                        fail(line_no, "expected 'facet normal nx ny nz' or 'endsolid'");
                    ++triangle;
                    expect = Expect::outer;
                    break;
                case Expect::outer:
                    if (!is("outer") || w.size() != 2 || !iequals(w[1], "loop")) fail(line_no, "expected 'outer loop'");
                    expect = Expect::vertex;
                    corner = 0;
                    break;
                case Expect::vertex: {
                    if (!is("vertex")) fail(line_no, "expected 'vertex x y z' (a triangle has 3 vertices)");
                    if (w.size() != 4) fail(line_no, "expected 3 coordinates after 'vertex'");
                    for (int k = 0; k < 3; ++k)
                        if (!parse_double(w[k + 1], corners[corner][k])) fail(line_no, "'" + std::string(w[k + 1]) + "' is not a number");
                    add_vertex(mesh, path, triangle, corner + 1, corners[corner], " (line " + std::to_string(line_no) + ")");
                    if (++corner == 3) {
                        if (mesh.vertices.size() > 0xfffffff0u) fail(line_no, "too many triangles");
                        const auto i = static_cast<std::uint32_t>(mesh.vertices.size() - 3);
                        mesh.triangles.push_back({i, i + 1, i + 2});
                        expect = Expect::endloop;
                    }
                    break;
                }
                case Expect::endloop:
                    if (!is("endloop")) fail(line_no, "expected 'endloop' (a triangle has 3 vertices)");
                    expect = Expect::endfacet;
                    break;
                case Expect::endfacet:
                    if (!is("endfacet")) fail(line_no, "expected 'endfacet'");
                    expect = Expect::facet;
                    break;
            }
        }
        if (expect != Expect::solid || solids == 0)
            fail(line_no, "the file ends before 'endsolid' (truncated?)");
    }
};

}  // namespace

TriangleMesh read_stl(const std::string& path) {
    const std::string bytes = read_mesh_bytes(path);
    const std::string_view b(bytes);
    const bool solid = starts_with_solid(b);
    const std::uint64_t n = b.size() >= 84 ? le32(b.data() + 80) : 0;
    const bool binary_size = b.size() >= 84 && 84 + 50 * n == b.size();
    TriangleMesh mesh;
    if (binary_size) {
        mesh = read_binary(path, b, n);
    } else if (solid) {
        AsciiStl r{path, false, "", {}};
        for (char c : b.substr(0, 4096))
            if ((static_cast<unsigned char>(c) < 9 || (c > 13 && c < 32)) && c != 0x1a) r.looks_binary = true;
        if (b.size() >= 84)
            r.binary_note = " (the file holds binary bytes: if it is a binary STL, its header declares " + std::to_string(n) +
                            " triangles, 84 + 50 n = " + std::to_string(84 + 50 * n) + " bytes, but it has " +
                            std::to_string(b.size()) + ": truncated, or a wrong count)";
        else
            r.binary_note = " (the file holds binary bytes, and is shorter than the 84 bytes of a binary STL header)";
        r.read(b);
        mesh = std::move(r.mesh);
    } else if (b.substr(0, 4) == "ply\n" || b.substr(0, 5) == "ply\r\n") {
        throw SceneError(path + ": this is a PLY file, not STL (name it .ply)");
    } else if (b.size() < 84) {
        throw SceneError(path + ": not an STL file: it does not start with 'solid' (ASCII STL) and has " +
                         std::to_string(b.size()) + " bytes, fewer than the 84 of a binary STL's header");
    } else {
        throw SceneError(path + ": binary STL: the header declares " + std::to_string(n) + " triangles, 84 + 50 n = " +
                         std::to_string(84 + 50 * n) + " bytes, but the file has " + std::to_string(b.size()) +
                         " (truncated, or a wrong count)");
    }
    weld_vertices(mesh);
    if (mesh.triangles.empty())
        throw SceneError(path + ": the mesh has no faces (no triangle with 3 distinct vertices)");
    return mesh;
}

}  // namespace clsph::scene
