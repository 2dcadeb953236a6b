// The free surface's work on one device (kernels/surface.cl, kernels/marching_cubes.cl), its
// buffers kept on the device from pass to pass: blocks counted from the owned fluid particles,
// the active ones flagged and compacted by a scan, sampled, meshed and welded; the host reads
// back only counts, and the mesh at the end. surface/extract.cpp runs it on every device and
// joins the devices' parts.
#pragma once
#include "cl/device.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"
#include "device/primitives.hpp"
#include "surface/marching_cubes.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace clsph::surface {

constexpr std::uint32_t kBlockCubes = 8;                  // cubes per block edge
constexpr std::uint32_t kBlockSamples = kBlockCubes + 1;  // samples per block edge (faces shared)
constexpr std::size_t kBlockPoints = std::size_t{kBlockSamples} * kBlockSamples * kBlockSamples;

// The lattice the surface is sampled on: sample (I, J, K) at origin + spacing (I, J, K), in blocks
// of 8^3 cubes; block (i, j, k) has key i + nx (j + ny k).
struct BlockLattice {
    std::array<double, 3> origin{};
    double spacing = 0;
    std::array<std::uint32_t, 3> blocks{};
    double edge() const { return kBlockCubes * spacing; }
    std::size_t count() const { return std::size_t{blocks[0]} * blocks[1] * blocks[2]; }
    std::array<std::uint32_t, 3> coords(std::uint32_t key) const {
        return {key % blocks[0], (key / blocks[0]) % blocks[1], key / (blocks[0] * blocks[1])};
    }
};

// A device's part of the mesh, on the host: edge[v] names vertex v's lattice edge
// (((K ny + J) nx + I) 3 + axis, over the lattice's samples) for the weld across devices.
struct MeshPart {
    std::vector<std::array<float, 3>> positions, normals;
    std::vector<std::uint64_t> edges;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

class DeviceSurface {
public:
    DeviceSurface(cl_rt::Device& device, const device::Grid& grid, const device::Physics& physics,
                  const BlockLattice& lattice);
    // Fluid particles per block, from the particles `store` owns.
    void count(const device::ParticleStore& store);
    std::vector<std::uint32_t> read_counts();
    void write_counts(const std::vector<std::uint32_t>& counts);
    // The active blocks, in key order: holding fluid or next to a block that does, unless the
    // block and its 26 neighbours all hold at least `full` fluid particles. Returns how many (a
    // blocking read of the scan's total).
    std::size_t activate(std::uint32_t full);
    std::vector<std::uint32_t> active_keys();
    // The fluid fraction at every sample of the active blocks, 0 at samples outside the columns
    // [col_lo, col_hi) along the split axis (the columns this device holds the particles of).
    void sample(device::ParticleStore& store, const device::CellPipeline& cells, std::uint32_t col_lo,
                std::uint32_t col_hi);
    std::vector<float> read_block(std::size_t slot);
    void write_block(std::size_t slot, const std::vector<float>& values);
    // Keeps only the active blocks at `slots` (ascending), in that order: the blocks this device
    // meshes when several share the surface.
    void keep(const std::vector<std::uint32_t>& slots);
    // Marching cubes over the blocks kept, vertices welded across their shared faces.
    void mesh(float iso);
    MeshPart download();
    // The welded mesh where it is (float4 positions and normals, 3 uint per triangle).
    const cl_rt::Buffer& positions() const { return position_; }
    const cl_rt::Buffer& normals() const { return normal_; }
    const cl_rt::Buffer& triangles() const { return triangles_; }
    std::size_t triangle_count() const { return triangle_count_; }
    std::size_t vertex_count() const { return vertices_; }
    cl_rt::Device& device() const { return device_; }

private:
    cl_rt::Device& device_;
    const device::Grid& grid_;
    const device::Physics& physics_;
    BlockLattice lattice_;
    device::Scan scan_;
    MarchingCubes mc_;
    cl::Kernel count_k_, flag_k_, compact_k_, field_k_, gather_k_, slots_k_, weld_k_, welded_k_, remap_k_;
    std::size_t wg_, field_wg_;
    cl_rt::Buffer counts_, active_, block_at_, field_;
    std::size_t blocks_ = 0;  // active blocks (kept)
    // The welded mesh: float4 positions and normals, uint2 edges, 3 uint per triangle.
    cl_rt::Buffer position_, normal_, edge_, triangles_;
    std::size_t vertices_ = 0, triangle_count_ = 0;
};

// The active blocks' keys computed on the host from fluid positions (the rule of activate()): the
// reference the tests hold the devices to.
std::vector<std::uint32_t> active_blocks_reference(const std::vector<std::array<double, 3>>& fluid,
                                                   const BlockLattice& lattice, std::uint32_t full);

}  // namespace clsph::surface
