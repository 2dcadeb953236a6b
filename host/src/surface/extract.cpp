#include "surface/extract.hpp"

#include "clsph/error.hpp"
#include "surface/marching_cubes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <unordered_set>

namespace clsph::surface {
namespace {

constexpr std::uint32_t kCubes = 8;            // cubes per block edge
constexpr std::uint32_t kSamples = kCubes + 1;  // samples per block edge (faces shared with neighbours)
constexpr double kFull = 0.9;                   // a block this full of fluid, with full neighbours, is inside
constexpr std::size_t kBatch = 2048;            // blocks sampled and meshed at once (1.5 M samples)

struct Lattice {
    std::array<double, 3> origin{};
    double spacing = 0;
    std::array<std::uint64_t, 3> blocks{};  // per axis
    std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return static_cast<std::uint64_t>(i) + blocks[0] * (static_cast<std::uint64_t>(j) + blocks[1] * static_cast<std::uint64_t>(k));
    }
    std::array<std::int64_t, 3> coords(std::uint64_t key) const {
        return {static_cast<std::int64_t>(key % blocks[0]), static_cast<std::int64_t>((key / blocks[0]) % blocks[1]),
                static_cast<std::int64_t>(key / (blocks[0] * blocks[1]))};
    }
    bool inside(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return i >= 0 && j >= 0 && k >= 0 && static_cast<std::uint64_t>(i) < blocks[0] &&
               static_cast<std::uint64_t>(j) < blocks[1] && static_cast<std::uint64_t>(k) < blocks[2];
    }
};

}  // namespace

TriangleMesh extract_surface(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                             const SurfaceOptions& options) {
    const double dp = scene.physics.dp;
    Lattice L;
    L.spacing = options.spacing > 0 ? options.spacing : 0.5 * dp;
    if (!std::isfinite(L.spacing) || !(options.iso > 0) || !(options.iso < 1))
        throw Error("surface: the spacing must be positive and iso within (0, 1)");
    for (int a = 0; a < 3; ++a) {
        L.origin[static_cast<std::size_t>(a)] = scene.domain.min[static_cast<std::size_t>(a)];
        const double extent = scene.domain.max[static_cast<std::size_t>(a)] - scene.domain.min[static_cast<std::size_t>(a)];
        L.blocks[static_cast<std::size_t>(a)] = static_cast<std::uint64_t>(std::ceil(extent / (kCubes * L.spacing))) + 1;
    }
    if (static_cast<double>(L.blocks[0]) * static_cast<double>(L.blocks[1]) * static_cast<double>(L.blocks[2]) > 1e15)
        throw Error("surface: the sample spacing is far too fine for the domain");

    // Fluid particles per block.
    const Particles p = driver.download();
    std::unordered_map<std::uint64_t, std::uint32_t> count;
    const double block_edge = kCubes * L.spacing;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::fluid) continue;
        std::int64_t c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = static_cast<std::int64_t>(std::floor((p.position[i][static_cast<std::size_t>(a)] - L.origin[static_cast<std::size_t>(a)]) / block_edge));
        if (L.inside(c[0], c[1], c[2])) ++count[L.key(c[0], c[1], c[2])];
    }
    const double full = kFull * std::pow(block_edge / dp, 3);
    auto is_full = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        if (!L.inside(i, j, k)) return false;
        const auto it = count.find(L.key(i, j, k));
        return it != count.end() && it->second >= full;
    };
    // Blocks to sample: holding fluid or next to it, unless inside.
    std::unordered_set<std::uint64_t> candidates;
    for (const auto& [key, n] : count) {
        (void)n;
        const auto c = L.coords(key);
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    if (L.inside(c[0] + di, c[1] + dj, c[2] + dk)) candidates.insert(L.key(c[0] + di, c[1] + dj, c[2] + dk));
    }
    std::vector<std::uint64_t> active;
    for (const auto key : candidates) {
        const auto c = L.coords(key);
        bool inside = true;
        for (int dk = -1; dk <= 1 && inside; ++dk)
            for (int dj = -1; dj <= 1 && inside; ++dj)
                for (int di = -1; di <= 1 && inside; ++di) inside = is_full(c[0] + di, c[1] + dj, c[2] + dk);
        if (!inside) active.push_back(key);
    }
    std::sort(active.begin(), active.end());

    // Each block to the slab owning its first sample's column.
    auto& slabs = driver.slabs();
    const int split = grid.axis(0);
    auto slab_of = [&](const std::array<double, 3>& x) {
        std::array<float, 3> off{};
        const auto key = grid.locate(x, off);
        std::size_t column = 0;
        if (key != grid.params().invalid_key) {
            column = grid.cell_of_key(key)[0];
        } else {  // outside the domain: the nearest column along the split axis
            const double rel = (x[static_cast<std::size_t>(split)] - scene.domain.min[static_cast<std::size_t>(split)]) / grid.params().cell_s;
            column = rel <= 0 ? 0 : std::min<std::size_t>(static_cast<std::size_t>(rel), grid.params().n_s - 1);
        }
        for (std::size_t d = 0; d < slabs.size(); ++d)
            if (column >= slabs[d].first_col && column < slabs[d].end_col) return d;
        for (std::size_t d = 0; d < slabs.size(); ++d)  // idle devices own no columns; the next busy one does
            if (slabs[d].end_col > slabs[d].first_col && column < slabs[d].end_col) return d;
        return slabs.size() - 1;
    };
    std::vector<std::vector<std::uint64_t>> per_slab(slabs.size());
    auto origin_of = [&](std::uint64_t key) {
        const auto c = L.coords(key);
        std::array<double, 3> o{};
        for (int a = 0; a < 3; ++a)
            o[static_cast<std::size_t>(a)] = L.origin[static_cast<std::size_t>(a)] + block_edge * static_cast<double>(c[static_cast<std::size_t>(a)]);
        return o;
    };
    for (const auto key : active) per_slab[slab_of(origin_of(key))].push_back(key);

    // Sample, mesh on the owning device, weld by lattice edge.
    TriangleMesh mesh;
    std::unordered_map<std::uint64_t, std::uint32_t> vertex_of_edge;
    const std::uint64_t lattice_x = L.blocks[0] * kCubes + 1, lattice_y = L.blocks[1] * kCubes + 1;
    const std::size_t per_block = std::size_t{kSamples} * kSamples * kSamples;
    std::array<float, 3> period_end{};  // the lattice's first plane at or past a periodic axis' max face
    for (std::size_t a = 0; a < 3; ++a) {
        const double extent = scene.domain.max[a] - scene.domain.min[a];
        period_end[a] = static_cast<float>(L.origin[a] + L.spacing * std::ceil(extent / L.spacing - 1e-9));
    }
    std::vector<std::unique_ptr<MarchingCubes>> mc(slabs.size());
    for (std::size_t d = 0; d < slabs.size(); ++d)
        if (!per_slab[d].empty()) mc[d] = std::make_unique<MarchingCubes>(*slabs[d].device);
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        // In batches of blocks, so that the samples' buffers (host and device) stay bounded
        // whatever the size of the surface.
        const auto& all = per_slab[d];
        for (std::size_t first = 0; first < all.size(); first += kBatch) {
        const std::vector<std::uint64_t> blocks(all.begin() + static_cast<std::ptrdiff_t>(first),
                                                all.begin() + static_cast<std::ptrdiff_t>(std::min(all.size(), first + kBatch)));
        std::vector<std::array<double, 3>> points;
        std::vector<std::array<std::int32_t, 3>> block_at;
        points.reserve(blocks.size() * per_block);
        for (const auto key : blocks) {
            const auto c = L.coords(key);
            block_at.push_back({static_cast<std::int32_t>(c[0] * kCubes), static_cast<std::int32_t>(c[1] * kCubes),
                                static_cast<std::int32_t>(c[2] * kCubes)});
            for (std::uint32_t k = 0; k < kSamples; ++k)
                for (std::uint32_t j = 0; j < kSamples; ++j)
                    for (std::uint32_t i = 0; i < kSamples; ++i)
                        points.push_back({L.origin[0] + L.spacing * (block_at.back()[0] + i), L.origin[1] + L.spacing * (block_at.back()[1] + j),
                                          L.origin[2] + L.spacing * (block_at.back()[2] + k)});
        }
        const auto sums = driver.probe(points);
        std::vector<float> field(points.size());
        for (std::size_t q = 0; q < points.size(); ++q) field[q] = sums[q][0];
        auto& dev = *slabs[d].device;
        auto buf = dev.alloc(field.size() * sizeof(float), "surface samples");
        dev.write(buf, field.data(), field.size());
        const BlockMeshes part =
            mc[d]->run_blocks(buf, {kSamples, kSamples, kSamples}, L.origin, L.spacing, block_at, static_cast<float>(options.iso));
        std::vector<std::uint32_t> global(part.mesh.positions.size());
        for (std::size_t v = 0; v < global.size(); ++v) {
            const std::uint32_t e = part.edge_of_vertex[v];
            const std::size_t b = e / (3 * per_block), local = e % (3 * per_block);
            const std::uint32_t sample = static_cast<std::uint32_t>(local / 3), axis = static_cast<std::uint32_t>(local % 3);
            const auto c = L.coords(blocks[b]);
            const std::uint64_t I = static_cast<std::uint64_t>(c[0]) * kCubes + sample % kSamples;
            const std::uint64_t J = static_cast<std::uint64_t>(c[1]) * kCubes + (sample / kSamples) % kSamples;
            const std::uint64_t K = static_cast<std::uint64_t>(c[2]) * kCubes + sample / (kSamples * kSamples);
            const std::uint64_t edge = ((K * lattice_y + J) * lattice_x + I) * 3 + axis;
            const auto [it, added] = vertex_of_edge.emplace(edge, static_cast<std::uint32_t>(mesh.positions.size()));
            if (added) {
                mesh.positions.push_back(part.mesh.positions[v]);
                mesh.normals.push_back(part.mesh.normals[v]);
            }
            global[v] = it->second;
        }
        for (const auto& t : part.mesh.triangles) {
            // Along a periodic axis the samples beyond the domain's max face are the wrapped
            // ones: one period of the surface is kept, open at the periodic faces.
            bool beyond = false;
            for (int a = 0; a < 3; ++a) {
                if (!scene.domain.periodic[static_cast<std::size_t>(a)]) continue;
                float lowest = mesh.positions[global[t[0]]][static_cast<std::size_t>(a)];
                for (int v = 1; v < 3; ++v) lowest = std::min(lowest, mesh.positions[global[t[static_cast<std::size_t>(v)]]][static_cast<std::size_t>(a)]);
                beyond = beyond || lowest >= period_end[static_cast<std::size_t>(a)];
            }
            if (!beyond) mesh.triangles.push_back({global[t[0]], global[t[1]], global[t[2]]});
        }
        }
    }
    return mesh;
}

}  // namespace clsph::surface
