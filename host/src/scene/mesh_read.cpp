// Which reader a mesh file gets, the weld STL needs, and the closed-mesh check every format shares.
#include "scene/mesh_formats.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numeric>

namespace clsph::scene {
namespace {

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return ext;
}

const char* unknown_format = "not a mesh format clsph reads (the name must end in .obj, .stl or .ply)";

}  // namespace

MeshFormat mesh_format_of(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".obj") return MeshFormat::obj;
    if (ext == ".stl") return MeshFormat::stl;
    if (ext == ".ply") return MeshFormat::ply;
    throw SceneError(path + ": " + unknown_format);
}

std::string mesh_path_problem(const std::string& path) {
    if (std::string why = mesh_file_problem(path); !why.empty()) return why;
    const std::string ext = lower_extension(path);
    if (ext != ".obj" && ext != ".stl" && ext != ".ply") return unknown_format;
    return "";
}

std::string read_mesh_bytes(const std::string& path) {
    if (const std::string why = mesh_file_problem(path); !why.empty()) throw SceneError(path + ": cannot open mesh: " + why);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open mesh: " + std::strerror(errno) + mesh_install_hint(path));
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw SceneError(path + ": cannot read mesh: " + std::strerror(errno));
    if (bytes.size() > max_mesh_bytes) throw SceneError(path + ": cannot read mesh: it grew beyond 512 MiB while read");
    return bytes;
}

void weld_vertices(TriangleMesh& mesh) {
    const std::size_t nv = mesh.vertices.size();
    std::vector<std::uint32_t> order(nv), first(nv), renumber(nv);
    std::iota(order.begin(), order.end(), 0u);
    // Equal positions together, the earliest first among them.
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return mesh.vertices[a] < mesh.vertices[b] || (mesh.vertices[a] == mesh.vertices[b] && a < b);
    });
    for (std::size_t k = 0; k < nv; ++k)
        first[order[k]] = (k > 0 && mesh.vertices[order[k]] == mesh.vertices[order[k - 1]]) ? first[order[k - 1]] : order[k];
    std::vector<Vec3> kept;
    for (std::size_t v = 0; v < nv; ++v) {
        if (first[v] == v) {
            renumber[v] = static_cast<std::uint32_t>(kept.size());
            kept.push_back(mesh.vertices[v]);
        } else {
            renumber[v] = renumber[first[v]];  // first[v] < v: already numbered
        }
    }
    std::size_t out = 0;
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> w{renumber[t[0]], renumber[t[1]], renumber[t[2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;
        mesh.triangles[out++] = w;
    }
    mesh.triangles.resize(out);
    mesh.vertices = std::move(kept);
}

TriangleMesh read_mesh(const std::string& path) {
    switch (mesh_format_of(path)) {
        case MeshFormat::obj: return read_obj(path);
        case MeshFormat::stl: return read_stl(path);
        case MeshFormat::ply: return read_ply(path);
    }
    throw SceneError(path + ": " + unknown_format);
}

TriangleMesh read_closed_mesh(const std::string& path) {
    TriangleMesh mesh = read_mesh(path);
    require_closed(mesh, path);
    return mesh;
}

}  // namespace clsph::scene
