// Triangle meshes from Wavefront OBJ files: the `v` and `f` lines (faces fan-triangulated,
// `v/vt/vn` index forms and negative indices accepted), everything else ignored.
#pragma once
#include "clsph/scene.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph::scene {

struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Mesh files (OBJ, STL, PLY) are read only when they are regular files of at most this size.
constexpr std::size_t max_mesh_bytes = std::size_t{512} << 20;
// Vertex coordinates beyond this (m, before scale) are errors, as are NaN and infinity.
constexpr double max_coordinate = 1e9;
// Why `path` cannot be read as a mesh file ("" when it can), with the install hint for a missing one.
std::string mesh_file_problem(const std::string& path);

// Throws SceneError naming the file (and the line) when it cannot be read, has no faces, a
// coordinate that is not finite or out of range, or an index out of range. Faces that repeat a vertex (zero area) are dropped.
TriangleMesh read_obj(const std::string& path);

// Edges not shared by exactly two triangles, after welding vertices at the same position (OBJ
// exporters often repeat a position for each texture seam). 0 for a closed manifold mesh.
struct EdgeCount {
    std::size_t edges = 0, open = 0;
};
EdgeCount count_open_edges(const TriangleMesh& mesh);

// SceneError naming `path` unless the mesh is closed (count_open_edges finds no open edge).
void require_closed(const TriangleMesh& mesh, const std::string& path);

// read_obj, then require_closed.
TriangleMesh read_closed_obj(const std::string& path);

// Advice for a mesh file that is missing ("" when there is none): the meshes our scenes use come
// from Debian packages.
std::string mesh_install_hint(const std::string& path);

}  // namespace clsph::scene
