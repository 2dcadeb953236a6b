// The marching cubes case table, generated rather than typed in: for each of the 256 inside/outside
// patterns of a cube's corners, the triangles (as cube edges) that separate inside from outside.
// Faces with two diagonally opposite inside corners are resolved one way everywhere (the inside
// corners are cut off, never joined), so two cubes sharing a face always agree on it and the mesh
// of a closed level set is closed: every mesh edge is shared by exactly two triangles. Triangles
// are oriented with their normal pointing from inside to outside. Pure C++.
#pragma once
#include <array>
#include <cstdint>

#include "marching_cubes.h"

namespace clsph::surface {

// table[case][3 t + k]: edge of corner k of triangle t, 255 after the last triangle.
using CaseTable = std::array<std::array<std::uint8_t, CLSPH_MC_CASE_ENTRIES>, 256>;
const CaseTable& case_table();

// The two corners an edge joins (cube numbering of kernels/marching_cubes.h).
std::array<int, 2> edge_corners(int edge);
std::array<int, 3> corner_offset(int corner);

}  // namespace clsph::surface
