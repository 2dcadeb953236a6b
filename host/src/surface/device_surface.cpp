#include "surface/device_surface.hpp"

#include "cl/kernel_args.hpp"
#include "device/primitives_launch.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace clsph::surface {
using device::ensure_capacity;
namespace {
constexpr cl_uint kNone = 0xffffffffu;
}

DeviceSurface::DeviceSurface(cl_rt::Device& device, const device::Grid& grid, const device::Physics& physics,
                             const BlockLattice& lattice, const SurfaceCapacity& capacity)
    : device_(device),
      grid_(grid),
      physics_(physics),
      lattice_(lattice),
      scan_(device, device::Scan::Config{0, 0, "surface.scan"}),
      mc_(device),
      wg_(device.work_group_size(128)),
      field_wg_(device.work_group_size(256)),
      capacity_(capacity) {
    const std::string opts = physics.point_options() + " -DSURFACE_WG=" + std::to_string(field_wg_);
    count_k_ = device.kernel("surface.cl", "surface_count", opts);
    flag_k_ = device.kernel("surface.cl", "surface_flag", opts);
    compact_k_ = device.kernel("surface.cl", "surface_compact", opts);
    field_k_ = device.kernel("surface.cl", "surface_field", opts);
    gather_k_ = device.kernel("surface.cl", "surface_gather", opts);
    slots_k_ = device.kernel("surface.cl", "surface_slots", opts);
    weld_k_ = device.kernel("surface.cl", "surface_weld", opts);
    welded_k_ = device.kernel("surface.cl", "surface_welded", opts);
    remap_k_ = device.kernel("surface.cl", "surface_remap", opts);
    total_k_ = device.kernel("surface.cl", "surface_total", opts);
    const std::size_t n = lattice.count();
    counts_ = device.alloc(n * sizeof(cl_uint), "surface block counts");
    flags_ = device.alloc(n * sizeof(cl_uint), "surface block flags");
    slots_ = device.alloc((n + 1) * sizeof(cl_uint), "surface block slots");
    slot_of_ = device.alloc(n * sizeof(cl_uint), "surface block slot map");
    totals_ = device.alloc(4 * sizeof(cl_uint), "surface totals");
    device.fill(totals_, cl_uint{0}, 4);
}

namespace {
cl_uint4 blocks_arg(const BlockLattice& L) { return cl_uint4{{L.blocks[0], L.blocks[1], L.blocks[2], 0}}; }
std::size_t at_least_one(std::size_t n) { return std::max<std::size_t>(n, 1); }
}  // namespace

void DeviceSurface::total(const cl_rt::Buffer& scanned, std::size_t at, std::uint32_t which) {
    cl_rt::set_args(total_k_, scanned, cl_rt::checked_uint(at), which, totals_);
    device_.launch("surface.total", total_k_, 1, 1);
}

void DeviceSurface::count(const device::ParticleStore& store) {
    device_.fill(counts_, cl_uint{0}, lattice_.count());
    const std::size_t first = store.ranges.first_owned(), end = store.ranges.end_owned();
    cl_rt::set_args(count_k_, cl_rt::checked_uint(first), cl_rt::checked_uint(end), grid_.params(), blocks_arg(lattice_),
                    static_cast<float>(lattice_.edge()), store.pos, store.id, counts_);
    device_.launch("surface.count", count_k_, end - first, wg_);
}

std::vector<std::uint32_t> DeviceSurface::read_counts() {
    std::vector<std::uint32_t> c(lattice_.count());
    device_.read(counts_, c.data(), c.size());
    return c;
}

void DeviceSurface::write_counts(const std::vector<std::uint32_t>& counts) {
    if (counts.size() != lattice_.count()) throw Error("surface: block counts of the wrong size");
    device_.write(counts_, counts.data(), counts.size());
}

void DeviceSurface::activate(std::uint32_t full) {
    const std::size_t n = lattice_.count();
    blocks_ = capacity_.blocks;
    ensure_capacity(device_, active_, at_least_one(blocks_) * sizeof(cl_uint), "surface active blocks");
    ensure_capacity(device_, block_at_, at_least_one(blocks_) * 4 * sizeof(cl_int), "surface block positions");
    cl_rt::set_args(flag_k_, blocks_arg(lattice_), full, counts_, flags_);
    device_.launch("surface.flag", flag_k_, n, wg_);
    scan_.exclusive(flags_, slots_, n);
    total(slots_, n, 0);
    cl_rt::set_args(compact_k_, blocks_arg(lattice_), cl_rt::checked_uint(blocks_), flags_, slots_, active_, block_at_);
    device_.launch("surface.compact", compact_k_, n, wg_);
}

std::size_t DeviceSurface::active_blocks(std::uint32_t full) {
    cl_uint n = 0;
    device_.read(totals_, &n, 1);
    if (n > capacity_.blocks) {
        capacity_.blocks = n + n / 4 + 16;
        activate(full);
    }
    return n;
}

std::vector<std::uint32_t> DeviceSurface::active_keys() {
    std::vector<std::uint32_t> keys(blocks_);
    cl_uint live = 0;
    device_.read(totals_, &live, 1);
    keys.resize(std::min<std::size_t>(live, blocks_));
    device_.read(active_, keys.data(), keys.size());
    return keys;
}

void DeviceSurface::sample(device::ParticleStore& store, const device::CellPipeline& cells, std::uint32_t col_lo,
                           std::uint32_t col_hi) {
    ensure_capacity(device_, field_, at_least_one(blocks_) * kBlockPoints * sizeof(float), "surface samples");
    if (blocks_ == 0) return;
    // Every block of the capacity is written: those past the live count with 0 (outside).
    cl_rt::set_args(field_k_, cl_rt::checked_uint(blocks_), static_cast<float>(lattice_.spacing), col_lo, col_hi,
                    cl_rt::checked_uint(cells.cells()), grid_.params(), physics_.params(), block_at_, cells.cell_key(),
                    cells.cell_start(), store.pos, store.velrho, store.id, totals_, field_);
    device_.launch("surface.field", field_k_, blocks_ * field_wg_, field_wg_);  // a work-group per block
}

std::vector<float> DeviceSurface::read_block(std::size_t slot) {
    std::vector<float> v(kBlockPoints);
    device_.read(field_, v.data(), v.size(), slot * kBlockPoints);
    return v;
}

void DeviceSurface::write_block(std::size_t slot, const std::vector<float>& values) {
    device_.write(field_, values.data(), kBlockPoints, slot * kBlockPoints);
}

void DeviceSurface::keep(const std::vector<std::uint32_t>& slots) {
    const std::size_t n = slots.size();
    auto slot_buf = device_.alloc(at_least_one(n) * sizeof(cl_uint), "surface kept blocks");
    auto active = device_.alloc(at_least_one(n) * sizeof(cl_uint), "surface active blocks");
    auto at = device_.alloc(at_least_one(n) * 4 * sizeof(cl_int), "surface block positions");
    auto field = device_.alloc(at_least_one(n) * kBlockPoints * sizeof(float), "surface samples");
    if (n > 0) {
        device_.write(slot_buf, slots.data(), n);
        cl_rt::set_args(gather_k_, cl_rt::checked_uint(n), slot_buf, active_, block_at_, field_, active, at, field);
        device_.launch("surface.gather", gather_k_, n * kBlockPoints, wg_);
    }
    active_ = std::move(active);
    block_at_ = std::move(at);
    field_ = std::move(field);
    blocks_ = n;
    const auto live = static_cast<cl_uint>(n);
    device_.write(totals_, &live, 1);
}

void DeviceSurface::mesh(float iso) {
    const std::size_t vcap = capacity_.vertices, tcap = capacity_.triangles;
    mc_.run_blocks_capacity(field_, {kBlockSamples, kBlockSamples, kBlockSamples}, lattice_.origin, lattice_.spacing,
                            block_at_, blocks_, vcap, tcap, iso, raw_);
    const std::size_t edges = 3 * kBlockPoints * blocks_, cubes = std::size_t{kBlockCubes} * kBlockCubes * kBlockCubes * blocks_;
    ensure_capacity(device_, own_, (vcap + 1) * sizeof(cl_uint), "surface weld flags");
    ensure_capacity(device_, target_, at_least_one(vcap) * sizeof(cl_uint), "surface weld targets");
    ensure_capacity(device_, welded_, (vcap + 1) * sizeof(cl_uint), "surface welded indices");
    ensure_capacity(device_, remap_, at_least_one(vcap) * sizeof(cl_uint), "surface vertex remap");
    ensure_capacity(device_, position_, at_least_one(vcap) * 4 * sizeof(float), "surface positions (welded)");
    ensure_capacity(device_, normal_, at_least_one(vcap) * 4 * sizeof(float), "surface normals (welded)");
    ensure_capacity(device_, edge_, at_least_one(vcap) * 2 * sizeof(cl_uint), "surface vertex edges (welded)");
    if (blocks_ == 0) {
        device_.fill(totals_, cl_uint{0}, 3, 1);
        return;
    }
    total(raw_.vertex_of, edges, 1);
    total(raw_.first_triangle, cubes, 2);
    // The weld: each lattice edge keeps the vertex of the lowest-keyed block meshed here.
    device_.fill(slot_of_, kNone, lattice_.count());
    cl_rt::set_args(slots_k_, cl_rt::checked_uint(blocks_), totals_, active_, slot_of_);
    device_.launch("surface.slots", slots_k_, blocks_, wg_);
    cl_rt::set_args(weld_k_, cl_rt::checked_uint(vcap), totals_, blocks_arg(lattice_), block_at_, slot_of_,
                    raw_.edge_of_vertex, raw_.vertex_of, own_, target_);
    device_.launch("surface.weld", weld_k_, vcap, wg_);
    scan_.exclusive(own_, welded_, vcap);
    total(welded_, vcap, 3);
    const cl_uint4 lattice{{lattice_.blocks[0] * kBlockCubes + 1, lattice_.blocks[1] * kBlockCubes + 1, 0, 0}};
    cl_rt::set_args(welded_k_, cl_rt::checked_uint(vcap), totals_, lattice, own_, welded_, target_, raw_.position,
                    raw_.normal, raw_.edge_of_vertex, block_at_, remap_, position_, normal_, edge_);
    device_.launch("surface.welded", welded_k_, vcap, wg_);
    // The triangles remapped in place onto the welded vertices.
    cl_rt::set_args(remap_k_, cl_rt::checked_uint(tcap), cl_rt::checked_uint(vcap), totals_, remap_, raw_.triangle_vertices);
    device_.launch("surface.remap", remap_k_, 3 * tcap, wg_);
}

bool DeviceSurface::settle() {
    cl_uint t[4] = {0, 0, 0, 0};
    device_.read(totals_, t, 4);
    const bool fits = t[0] <= blocks_ && t[1] <= capacity_.vertices && t[2] <= capacity_.triangles;
    if (fits) {
        vertices_ = t[3];
        triangle_count_ = t[2];
        return true;
    }
    vertices_ = triangle_count_ = 0;
    // Grown with a margin; where the blocks were short the other counts covered only the blocks
    // kept, so they grow in proportion too.
    const double short_by = blocks_ > 0 && t[0] > blocks_ ? static_cast<double>(t[0]) / static_cast<double>(blocks_) : 1.0;
    auto grow = [&](std::size_t& cap, double need) {
        if (need > static_cast<double>(cap)) cap = static_cast<std::size_t>(need * 1.25) + 64;
    };
    grow(capacity_.blocks, t[0]);
    const double per_block_v = blocks_ > 0 ? 0.0 : 24.0, per_block_t = blocks_ > 0 ? 0.0 : 40.0;  // a first guess (a tank in the tests: ~14 and ~22)
    grow(capacity_.vertices, std::max(static_cast<double>(t[1]) * short_by, per_block_v * t[0]));
    grow(capacity_.triangles, std::max(static_cast<double>(t[2]) * short_by, per_block_t * t[0]));
    return false;
}

MeshPart DeviceSurface::download() {
    MeshPart part;
    if (vertices_ == 0) return part;
    std::vector<float> p(4 * vertices_), q(4 * vertices_);
    std::vector<cl_uint> e(2 * vertices_), t(3 * triangle_count_);
    device_.read(position_, p.data(), p.size());
    device_.read(normal_, q.data(), q.size());
    device_.read(edge_, e.data(), e.size());
    if (triangle_count_ > 0) device_.read(raw_.triangle_vertices, t.data(), t.size());
    part.positions.resize(vertices_);
    part.normals.resize(vertices_);
    part.edges.resize(vertices_);
    for (std::size_t v = 0; v < vertices_; ++v) {
        part.positions[v] = {p[4 * v], p[4 * v + 1], p[4 * v + 2]};
        part.normals[v] = {q[4 * v], q[4 * v + 1], q[4 * v + 2]};
        part.edges[v] = std::uint64_t{e[2 * v]} | (std::uint64_t{e[2 * v + 1]} << 32);
    }
    part.triangles.resize(triangle_count_);
    for (std::size_t k = 0; k < triangle_count_; ++k) part.triangles[k] = {t[3 * k], t[3 * k + 1], t[3 * k + 2]};
    return part;
}

std::vector<std::uint32_t> active_blocks_reference(const std::vector<std::array<double, 3>>& fluid,
                                                   const BlockLattice& L, std::uint32_t full) {
    const std::int64_t n[3] = {L.blocks[0], L.blocks[1], L.blocks[2]};
    std::unordered_map<std::uint32_t, std::uint32_t> count;
    auto key = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        return static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
    };
    auto inside = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        return i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2];
    };
    for (const auto& x : fluid) {
        std::int64_t c[3];
        for (std::size_t a = 0; a < 3; ++a) c[a] = static_cast<std::int64_t>(std::floor((x[a] - L.origin[a]) / L.edge()));
        if (inside(c[0], c[1], c[2])) ++count[key(c[0], c[1], c[2])];
    }
    std::vector<std::uint32_t> active;
    for (std::int64_t k = 0; k < n[2]; ++k)
        for (std::int64_t j = 0; j < n[1]; ++j)
            for (std::int64_t i = 0; i < n[0]; ++i) {
                bool wet = false, all_full = true;
                for (int dk = -1; dk <= 1; ++dk)
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            if (!inside(i + di, j + dj, k + dk)) {
                                all_full = false;
                                continue;
                            }
                            const auto it = count.find(key(i + di, j + dj, k + dk));
                            const std::uint32_t c = it == count.end() ? 0 : it->second;
                            wet = wet || c > 0;
                            all_full = all_full && c >= full;
                        }
                if (wet && !all_full) active.push_back(key(i, j, k));
            }
    return active;
}

}  // namespace clsph::surface
