#include "scene/mesh_obj.hpp"

#include "clsph/error.hpp"
#include "io/file.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>

namespace clsph::scene {
namespace {

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

bool parse_double(std::string_view s, double& out) {
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return r.ec == std::errc() && r.ptr == end;
}

struct ObjReader {
    std::string path;
    TriangleMesh mesh;
    std::vector<std::size_t> triangle_line;  // for errors about indices found out of range later

    [[noreturn]] void fail(std::size_t line, const std::string& what) const {
        throw SceneError(path + ": line " + std::to_string(line) + ": " + what);
    }

    void vertex(const std::vector<std::string_view>& w, std::size_t line) {
        Vec3 v{};
        if (w.size() < 4) fail(line, "expected 3 coordinates after 'v'");
        for (int k = 0; k < 3; ++k) {
            if (!parse_double(w[k + 1], v[k]))
                fail(line, "'" + std::string(w[k + 1]) + "' is not a number");
            // NaN, infinity and coordinates no scene could hold (from_chars reads "nan" and "1e300").
            if (!std::isfinite(v[k]) || std::abs(v[k]) > max_coordinate)
                fail(line, "vertex coordinate '" + std::string(w[k + 1]) + "' is not a finite number of at most 1e9 in size");
        }
        mesh.vertices.push_back(v);
    }

    // "7", "7/2", "7//3", "7/2/3"; negative indices count back from the last vertex read so far.
    std::int64_t index(std::string_view word, std::size_t line) const {
        std::int64_t i = 0;
        const auto r = std::from_chars(word.data(), word.data() + word.size(), i);
        if (r.ec != std::errc() || (r.ptr != word.data() + word.size() && *r.ptr != '/'))
            fail(line, "'" + std::string(word) + "' is not a vertex index");
        if (i == 0) fail(line, "vertex index 0 (OBJ indices start at 1)");
        if (i < 0) {
            const auto resolved = static_cast<std::int64_t>(mesh.vertices.size()) + i;
            if (resolved < 0)
                fail(line, "vertex index " + std::to_string(i) + " reaches before the first vertex");
            return resolved;
        }
        return i - 1;
    }

    void face(const std::vector<std::string_view>& w, std::size_t line) {
        if (w.size() < 4) fail(line, "a face needs at least 3 vertices");
        std::vector<std::int64_t> f;
        for (std::size_t k = 1; k < w.size(); ++k) f.push_back(index(w[k], line));
        for (std::size_t k = 1; k + 1 < f.size(); ++k) {  // a fan around the first vertex
            const std::int64_t a = f[0], b = f[k], c = f[k + 1];
            if (std::max({a, b, c}) > 0xffffffffLL) fail(line, "vertex index too large");
            if (a == b || b == c || a == c) continue;  // zero area: no surface to keep
            mesh.triangles.push_back(
                {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)});
            triangle_line.push_back(line);
        }
    }

    void check_indices() const {
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            for (auto i : mesh.triangles[t])
                if (i >= mesh.vertices.size())
                    fail(triangle_line[t], "vertex index " + std::to_string(std::uint64_t{i} + 1) +
                                               " is out of range (the file has " +
                                               std::to_string(mesh.vertices.size()) + " vertices)");
    }
};

}  // namespace

std::string mesh_install_hint(const std::string& path) {
    if (path.find("/glmark2/") != std::string::npos)
        return " (this mesh comes with Debian's glmark2-data package: apt-get install glmark2-data)";
    return "";
}

std::string mesh_file_problem(const std::string& path) {
    std::string why = io::file_problem(path, max_mesh_bytes);
    if (why == std::strerror(ENOENT)) why += mesh_install_hint(path);
    return why;
}

TriangleMesh read_obj(const std::string& path) {
    if (const std::string why = mesh_file_problem(path); !why.empty()) throw SceneError(path + ": cannot open mesh: " + why);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open mesh: " + std::strerror(errno) + mesh_install_hint(path));
    ObjReader r{path, {}, {}};
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        std::string_view text(line);
        if (const auto hash = text.find('#'); hash != std::string_view::npos) text = text.substr(0, hash);
        while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.remove_suffix(1);
        const auto words = split_words(text);
        if (words.empty()) continue;
        if (words[0] == "v")
            r.vertex(words, line_no);
        else if (words[0] == "f")
            r.face(words, line_no);
        // vt, vn, o, g, s, usemtl, mtllib, l, ...: nothing we need
    }
    if (in.bad()) throw SceneError(path + ": cannot read mesh: " + std::strerror(errno));
    if (r.mesh.triangles.empty())
        throw SceneError(path + ": the mesh has no faces (no 'f' lines with 3 or more distinct vertices)");
    r.check_indices();
    return std::move(r.mesh);
}

EdgeCount count_open_edges(const TriangleMesh& mesh) {
    // Weld: every vertex maps to the first vertex at exactly the same position.
    const std::size_t nv = mesh.vertices.size();
    std::vector<std::uint32_t> order(nv), weld(nv);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return mesh.vertices[a] < mesh.vertices[b]; });
    for (std::size_t k = 0; k < nv; ++k)
        weld[order[k]] = (k > 0 && mesh.vertices[order[k]] == mesh.vertices[order[k - 1]]) ? weld[order[k - 1]] : order[k];

    std::vector<std::uint64_t> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
        const std::uint32_t v[3] = {weld[t[0]], weld[t[1]], weld[t[2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // collapsed by the weld
        for (int e = 0; e < 3; ++e) {
            const std::uint64_t a = std::min(v[e], v[(e + 1) % 3]), b = std::max(v[e], v[(e + 1) % 3]);
            edges.push_back(a << 32 | b);
        }
    }
    std::sort(edges.begin(), edges.end());
    EdgeCount count;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        ++count.edges;
        if (j - i != 2) ++count.open;
        i = j;
    }
    return count;
}

void require_closed(const TriangleMesh& mesh, const std::string& path) {
    const EdgeCount e = count_open_edges(mesh);
    if (e.open > 0)
        throw SceneError(path + ": the mesh is not closed: " + std::to_string(e.open) + " of " + std::to_string(e.edges) +
                         " edges are not shared by exactly two triangles (inside and outside are only defined for "
                         "a closed, watertight surface)");
}

TriangleMesh read_closed_obj(const std::string& path) {
    TriangleMesh mesh = read_obj(path);
    require_closed(mesh, path);
    return mesh;
}

}  // namespace clsph::scene
