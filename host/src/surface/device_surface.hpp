// The free surface's work on one device (kernels/surface.cl, kernels/marching_cubes.cl): blocks
// counted from the owned fluid particles, the active ones flagged and compacted by a scan,
// sampled, meshed and welded. Its buffers are sized by capacities (blocks, vertices, triangles)
// and kept from surface to surface; the counts stay on the device (totals()), each kernel bounded
// by them, so one device's surface costs no read-back. settle() reads the four totals once at the
// end: a count past its capacity grows the capacity, and the surface is taken again (a redo, as
// the step ahead does). surface/extract.cpp runs it on every device and joins the devices' parts.
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

// What a device's surface buffers are sized for.
struct SurfaceCapacity {
    std::size_t blocks = 0, vertices = 0, triangles = 0;
};

class DeviceSurface {
public:
    DeviceSurface(cl_rt::Device& device, const device::Grid& grid, const device::Physics& physics,
                  const BlockLattice& lattice, const SurfaceCapacity& capacity = {});
    const BlockLattice& lattice() const { return lattice_; }
    const device::Physics& physics() const { return physics_; }
    const SurfaceCapacity& capacity() const { return capacity_; }
    // Fluid particles per block, from the particles `store` owns.
    void count(const device::ParticleStore& store);
    std::vector<std::uint32_t> read_counts();
    void write_counts(const std::vector<std::uint32_t>& counts);
    // The active blocks, in key order: holding fluid or next to a block that does, unless the
    // block and its 26 neighbours all hold at least `full` fluid particles. Their count stays on
    // the device (totals()[0]); at most capacity().blocks are kept.
    void activate(std::uint32_t full);
    // The number of active blocks (a blocking read), the capacity grown and the blocks compacted
    // again if it was short: for the several-device path, which joins them on the host.
    std::size_t active_blocks(std::uint32_t full);
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
    // Reads the totals (one blocking read of four uints): true when every count fitted its
    // capacity, and then triangle_count() and vertex_count() hold. False: the capacities have been
    // grown to fit, and the surface must be taken again from count().
    bool settle();
    MeshPart download();  // after settle()
    // On the device: active blocks, vertices before the weld, triangles, welded vertices (each
    // may exceed its capacity; the kernels stop at the capacity).
    const cl_rt::Buffer& totals() const { return totals_; }
    // The welded mesh where it is (float4 positions and normals, 3 uint per triangle).
    const cl_rt::Buffer& positions() const { return position_; }
    const cl_rt::Buffer& normals() const { return normal_; }
    const cl_rt::Buffer& triangles() const { return raw_.triangle_vertices; }
    std::size_t triangle_capacity() const { return capacity_.triangles; }
    std::size_t triangle_count() const { return triangle_count_; }  // after settle()
    std::size_t vertex_count() const { return vertices_; }           // after settle()
    cl_rt::Device& device() const { return device_; }

private:
    cl_rt::Device& device_;
    const device::Grid& grid_;
    const device::Physics& physics_;
    BlockLattice lattice_;
    device::Scan scan_;
    MarchingCubes mc_;
    cl::Kernel count_k_, flag_k_, compact_k_, field_k_, gather_k_, slots_k_, weld_k_, welded_k_, remap_k_, total_k_;
    std::size_t wg_, field_wg_;
    SurfaceCapacity capacity_;
    std::size_t blocks_ = 0;  // blocks the buffers hold: capacity_.blocks, or the kept blocks
    cl_rt::Buffer totals_, counts_, flags_, slots_, active_, block_at_, field_;
    DeviceBlockMeshes raw_;  // marching cubes' output, before the weld
    cl_rt::Buffer slot_of_, own_, target_, welded_, remap_;
    // The welded mesh: float4 positions and normals, uint2 edges, 3 uint per triangle.
    cl_rt::Buffer position_, normal_, edge_;  // the triangles: raw_.triangle_vertices, remapped
    std::size_t vertices_ = 0, triangle_count_ = 0;
    void total(const cl_rt::Buffer& scanned, std::size_t at, std::uint32_t which);
};

// The active blocks' keys computed on the host from fluid positions (the rule of activate()): the
// reference the tests hold the devices to.
std::vector<std::uint32_t> active_blocks_reference(const std::vector<std::array<double, 3>>& fluid,
                                                   const BlockLattice& lattice, std::uint32_t full);

}  // namespace clsph::surface
