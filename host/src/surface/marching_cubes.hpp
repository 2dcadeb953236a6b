// Marching cubes on one device (kernels/marching_cubes.cl): a triangle mesh of the level set
// value = iso of a field sampled on a regular grid, vertices welded (one per crossing grid edge),
// normals from the field's gradient, triangles oriented outwards (towards lower values). Also the
// same algorithm in plain C++, the reference the tests compare the device against.
#pragma once
#include "cl/device.hpp"
#include "clsph/mesh.hpp"
#include "device/primitives.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::surface {

struct SampleGrid {
    std::array<std::uint32_t, 3> points{2, 2, 2};  // samples per axis (>= 2)
    std::array<double, 3> origin{0, 0, 0};         // position of sample (0, 0, 0)
    double spacing = 1.0;                          // between neighbouring samples
    std::size_t samples() const { return std::size_t{points[0]} * points[1] * points[2]; }
};

using Mesh = TriangleMesh;  // clsph/mesh.hpp

// Meshes of a batch of blocks: vertices are welded within a block; edge_of_vertex[v] says which
// grid edge vertex v lies on: block b, sample p of the block, axis a as b (3 samples) + 3 p + a.
struct BlockMeshes {
    Mesh mesh;
    std::vector<std::uint32_t> edge_of_vertex;
};

// The same, left on the device (the free surface's path, surface/device_surface.hpp): only the
// two counts are read back. Per vertex: position and normal (float4), edge_of_vertex as in
// BlockMeshes; vertex_of: per block 3 per sample + 1, each crossing edge's vertex index;
// triangles: 3 vertex indices each.
struct DeviceBlockMeshes {
    std::size_t vertices = 0, triangles = 0;
    cl_rt::Buffer vertex_of, position, normal, edge_of_vertex, triangle_vertices;
    cl_rt::Buffer first_triangle;  // per cube + 1: the scan of triangles per cube (run_blocks_capacity)
};

class MarchingCubes {
public:
    explicit MarchingCubes(cl_rt::Device& device);
    // `field` holds grid.samples() floats, sample (i, j, k) at i + nx (j + ny k). Blocking: returns
    // the mesh on the host.
    Mesh run(const cl_rt::Buffer& field, const SampleGrid& grid, float iso);
    // Blocks of `points` samples each on one lattice (sample (i, j, k) at origin + spacing (i, j, k)):
    // block b's samples at b * (samples per block) in `field`, its sample (0, 0, 0) at lattice index
    // block_at[b]. Blocking.
    BlockMeshes run_blocks(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                           const std::array<double, 3>& origin, double spacing,
                           const std::vector<std::array<std::int32_t, 3>>& block_at, float iso);

    // `block_at` holds `blocks` int4 (lattice index of each block's sample (0, 0, 0)).
    DeviceBlockMeshes run_blocks_device(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                                        const std::array<double, 3>& origin, double spacing,
                                        const cl_rt::Buffer& block_at, std::size_t blocks, float iso);
    // The same with no read-back, into `out`'s buffers (grown to the capacities): `blocks` blocks
    // of `points` samples (blocks past the live ones hold 0, below iso: they make nothing), at
    // most `vertices` vertices and `triangles` triangles written. The totals, which may exceed the
    // capacities, stay on the device: out.vertex_of[edges()] and out.first_triangle[cubes()].
    void run_blocks_capacity(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                             const std::array<double, 3>& origin, double spacing, const cl_rt::Buffer& block_at,
                             std::size_t blocks, std::size_t vertices, std::size_t triangles, float iso,
                             DeviceBlockMeshes& out);

private:
    cl_rt::Device& device_;
    device::Scan scan_;
    cl::Kernel edges_k_, vertices_k_, cubes_k_, triangles_k_;
    cl_rt::Buffer table_;
    std::size_t wg_;
};

// The same mesh computed on the host (double interpolation, float output).
Mesh marching_cubes_reference(const std::vector<float>& field, const SampleGrid& grid, float iso);

}  // namespace clsph::surface
