#include "surface/extract.hpp"

#include "clsph/error.hpp"
#include "surface/device_surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>

namespace clsph::surface {
namespace {

constexpr double kFull = 0.9;  // a block this full of fluid, with full neighbours, is inside

BlockLattice lattice_for(const Scene& scene, const SurfaceOptions& options) {
    BlockLattice L;
    L.spacing = options.spacing > 0 ? options.spacing : 0.5 * scene.physics.dp;
    if (!std::isfinite(L.spacing) || !(options.iso > 0) || !(options.iso < 1))
        throw Error("surface: the spacing must be positive and iso within (0, 1)");
    double blocks = 1;
    for (std::size_t a = 0; a < 3; ++a) {
        L.origin[a] = scene.domain.min[a];
        const double n = std::ceil((scene.domain.max[a] - scene.domain.min[a]) / L.edge()) + 1;
        blocks *= n;
        if (n > 1e6) blocks = 1e30;
        else L.blocks[a] = static_cast<std::uint32_t>(n);
    }
    // The block counts are a dense grid on each device (4 bytes a block), and the lattice's
    // samples are numbered in 32 bits within it.
    if (blocks > 1.0e8 || blocks * kBlockCubes * kBlockCubes * kBlockCubes * 3 > 1.8e19)
        throw Error("surface: the sample spacing (surface spacing " + std::to_string(L.spacing) +
                    " m) is far too fine for the domain: " + std::to_string(blocks) + " blocks of 8^3 samples");
    return L;
}

}  // namespace

bool DeviceParts::settle() {
    bool fits = true;
    for (auto& p : parts)
        if (p) fits = p->settle() && fits;  // every part, so each grows what it lacked
    return fits;
}

namespace {
bool same_lattice(const BlockLattice& a, const BlockLattice& b) {
    return a.origin == b.origin && a.spacing == b.spacing && a.blocks == b.blocks;
}
}  // namespace

void surface_on_devices(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                        const SurfaceOptions& options, DeviceParts& into) {
    const BlockLattice L = lattice_for(scene, options);
    const double dp = scene.physics.dp;
    const auto full = static_cast<std::uint32_t>(std::ceil(kFull * std::pow(L.edge() / dp, 3)));
    auto& slabs = driver.slabs();
    std::vector<std::size_t> busy;  // slabs owning columns: they sample and mesh
    for (std::size_t d = 0; d < slabs.size(); ++d)
        if (!slabs[d].empty()) busy.push_back(d);
    auto& parts = into.parts;
    parts.resize(slabs.size());
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        const bool is_busy = std::find(busy.begin(), busy.end(), d) != busy.end();
        auto& p = parts[d];
        if (!is_busy) {
            p.reset();
            continue;
        }
        const bool reuse = p && &p->device() == slabs[d].device && &p->physics() == slabs[d].physics.get() &&
                           same_lattice(p->lattice(), L);
        if (!reuse) p = std::make_unique<DeviceSurface>(*slabs[d].device, grid, *slabs[d].physics, L);
    }
    if (busy.empty()) return;

    // Fluid per block: each device counts what it owns; several devices add their counts (the
    // flags need every neighbour's).
    for (auto d : busy) parts[d]->count(*slabs[d].store);
    if (busy.size() > 1) {
        std::vector<std::uint32_t> total(L.count(), 0);
        for (auto d : busy) {
            const auto c = parts[d]->read_counts();
            for (std::size_t k = 0; k < c.size(); ++k) total[k] += c[k];
        }
        for (auto d : busy) parts[d]->write_counts(total);
    }
    for (auto d : busy) parts[d]->activate(full);  // the same blocks on every device
    // Several devices join their blocks on the host, so they read the count now (one device
    // reads nothing until settle()).
    if (busy.size() > 1)
        for (auto d : busy) parts[d]->active_blocks(full);

    // Each sample is evaluated on the device owning its column (which holds the ghosts it needs).
    for (auto d : busy)
        parts[d]->sample(*slabs[d].store, *slabs[d].cells, static_cast<std::uint32_t>(slabs[d].first_col),
                         static_cast<std::uint32_t>(slabs[d].end_col));
    if (busy.size() > 1) {
        // Each block is meshed by the device owning its first sample's column; a block whose
        // samples reach other devices' columns (by a column more on each side, for round-off in
        // locating its samples) gets their values added in: each sample is non-zero on one device.
        const int split = grid.axis(0);
        const auto& gp = grid.params();
        auto column_of = [&](double x) {
            const double rel = std::floor((x - scene.domain.min[static_cast<std::size_t>(split)]) / gp.cell_s);
            return static_cast<std::int64_t>(std::clamp(rel, -1.0, static_cast<double>(gp.n_s)));
        };
        auto busy_of = [&](std::int64_t column) {  // the busy slab owning a column (clamped into the domain)
            const auto c = static_cast<std::size_t>(std::clamp<std::int64_t>(column, 0, static_cast<std::int64_t>(gp.n_s) - 1));
            for (auto d : busy)
                if (c >= slabs[d].first_col && c < slabs[d].end_col) return d;
            return busy.back();
        };
        const auto keys = parts[busy.front()]->active_keys();
        std::vector<std::vector<std::uint32_t>> mine(slabs.size());
        for (std::size_t slot = 0; slot < keys.size(); ++slot) {
            const auto c = L.coords(keys[slot]);
            const double x0 = L.origin[static_cast<std::size_t>(split)] + L.edge() * c[static_cast<std::size_t>(split)];
            const std::int64_t first = column_of(x0), last = column_of(x0 + L.edge());
            const std::size_t owner = busy_of(first);
            mine[owner].push_back(static_cast<std::uint32_t>(slot));
            std::vector<std::size_t> others;
            for (auto d : busy)
                if (d != owner && static_cast<std::int64_t>(slabs[d].end_col) > first - 1 &&
                    static_cast<std::int64_t>(slabs[d].first_col) <= last + 1)
                    others.push_back(d);
            if (others.empty()) continue;
            auto sum = parts[owner]->read_block(slot);
            for (auto d : others) {
                const auto v = parts[d]->read_block(slot);
                for (std::size_t q = 0; q < sum.size(); ++q) sum[q] += v[q];
            }
            parts[owner]->write_block(slot, sum);
        }
        for (auto d : busy) parts[d]->keep(mine[d]);
    }
    for (auto d : busy) parts[d]->mesh(static_cast<float>(options.iso));
}

void settled_surface(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                     const SurfaceOptions& options, DeviceParts& into) {
    for (int attempt = 0; attempt < 4; ++attempt) {
        surface_on_devices(driver, grid, scene, options, into);
        if (into.settle()) return;
    }
    throw Error("surface: the mesh's buffers did not settle after four attempts (a bug: please report it)");
}

TriangleMesh extract_surface(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene,
                             const SurfaceOptions& options, DeviceParts& on) {
    const BlockLattice L = lattice_for(scene, options);
    settled_surface(driver, grid, scene, options, on);
    std::vector<std::size_t> busy;
    for (std::size_t d = 0; d < on.parts.size(); ++d)
        if (on.parts[d]) busy.push_back(d);

    // One mesh: the devices' parts in order, welded where they meet (by lattice edge).
    TriangleMesh mesh;
    std::unordered_map<std::uint64_t, std::uint32_t> vertex_of_edge;
    std::array<float, 3> period_end{};  // the lattice's first plane at or past a periodic axis' max face
    for (std::size_t a = 0; a < 3; ++a) {
        const double extent = scene.domain.max[a] - scene.domain.min[a];
        period_end[a] = static_cast<float>(L.origin[a] + L.spacing * std::ceil(extent / L.spacing - 1e-9));
    }
    for (auto d : busy) {
        const MeshPart part = on.parts[d]->download();
        std::vector<std::uint32_t> global(part.positions.size());
        for (std::size_t v = 0; v < global.size(); ++v) {
            std::uint32_t at = static_cast<std::uint32_t>(mesh.positions.size());
            bool added = true;
            if (busy.size() > 1) {
                const auto [it, fresh] = vertex_of_edge.emplace(part.edges[v], at);
                at = it->second;
                added = fresh;
            }
            if (added) {
                mesh.positions.push_back(part.positions[v]);
                mesh.normals.push_back(part.normals[v]);
            }
            global[v] = at;
        }
        for (const auto& t : part.triangles) {
            // Along a periodic axis the samples beyond the domain's max face are the wrapped
            // ones: one period of the surface is kept, open at the periodic faces.
            bool beyond = false;
            for (std::size_t a = 0; a < 3; ++a) {
                if (!scene.domain.periodic[a]) continue;
                float lowest = mesh.positions[global[t[0]]][a];
                for (std::size_t v = 1; v < 3; ++v) lowest = std::min(lowest, mesh.positions[global[t[v]]][a]);
                beyond = beyond || lowest >= period_end[a];
            }
            if (!beyond) mesh.triangles.push_back({global[t[0]], global[t[1]], global[t[2]]});
        }
    }
    return mesh;
}

}  // namespace clsph::surface
