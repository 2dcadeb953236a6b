// Triangle meshes on disk: the free surface clsph extracts (marching cubes on the devices) as VTK
// XML PolyData (.vtp, ParaView; a series of them in a .pvd like the particle frames) or binary PLY
// (Blender, MeshLab). Files are written to "<path>.tmp" and renamed into place; errors are
// clsph::Error naming the path.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace clsph {

struct TriangleMesh {
    std::vector<std::array<float, 3>> positions;          // m
    std::vector<std::array<float, 3>> normals;            // unit, pointing out of the fluid (or empty)
    std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices, counter-clockwise seen from outside
};

// How Simulation::surface() extracts the free surface: the level `iso` of the fluid fraction
// sum_j (m_j / rho_j) W(|x - x_j|) over fluid particles (1 inside the fluid, 0 outside), sampled on a
// lattice of `spacing` from the domain's min corner, in blocks of 8^3 cubes near the surface only.
struct SurfaceOptions {
    double spacing = 0.0;  // m; 0: half the particle spacing dp
    double iso = 0.5;
};

// VTK XML PolyData, appended raw binary: points (Float32 x 3), point data "normal" (when given),
// polys (connectivity, offsets).
void write_vtp(const std::string& path, const TriangleMesh& mesh);
// PLY, binary in the host's byte order: vertex x y z [nx ny nz] (float), face vertex_indices
// (uchar count, uint indices).
void write_ply(const std::string& path, const TriangleMesh& mesh);
// Reads a file written by write_ply (for tests and tools, not PLY files in general).
TriangleMesh read_ply(const std::string& path);

}  // namespace clsph
