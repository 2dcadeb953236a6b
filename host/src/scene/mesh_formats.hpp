// Mesh files in every format a scene can name, chosen by the file name's extension (.obj, .stl,
// .ply, case-insensitive) and confirmed by the content. Every reader gives a TriangleMesh
// (scene/mesh_obj.hpp) or throws SceneError naming the file and the element (line, triangle,
// vertex, face) at fault; counts in a file are checked against its size before anything is
// allocated for them.
#pragma once
#include "scene/mesh_obj.hpp"

#include <string>

namespace clsph::scene {

enum class MeshFormat { obj, stl, ply };

// The format of `path` by its extension; SceneError naming the file when it has none of ours.
MeshFormat mesh_format_of(const std::string& path);
// Why `path` cannot be a mesh ("" when it can): mesh_file_problem, or an extension we do not read.
std::string mesh_path_problem(const std::string& path);

// STL, binary or ASCII (scene/mesh_stl.cpp). A file that starts with "solid" is ASCII unless its
// size is exactly that of a binary STL of the triangle count at byte 80 (84 + 50 n bytes): some
// exporters begin binary headers with "solid". Triangles share no vertices in STL; identical
// positions (exact equality) are welded into one vertex, and triangles left with a repeated
// vertex (zero area) are dropped.
TriangleMesh read_stl(const std::string& path);

// PLY, ASCII or binary of either byte order (scene/mesh_ply.cpp): the `vertex` element's x, y, z
// (any scalar type) and the `face` element's vertex_indices (or vertex_index) list, polygons
// fan-triangulated; every other element and property is skipped by its declared type.
TriangleMesh read_ply(const std::string& path);

// The reader of mesh_format_of(path).
TriangleMesh read_mesh(const std::string& path);

// read_mesh, then SceneError naming the file unless the mesh is closed (every edge shared by
// exactly two triangles after welding): inside and outside need a watertight surface.
TriangleMesh read_closed_mesh(const std::string& path);

// Welds vertices at exactly the same position into the first of them, renumbers the triangles
// and drops those left with a repeated vertex; vertices no triangle uses are kept.
void weld_vertices(TriangleMesh& mesh);

// The whole mesh file, after the checks of mesh_file_problem; SceneError naming it otherwise.
std::string read_mesh_bytes(const std::string& path);

}  // namespace clsph::scene
