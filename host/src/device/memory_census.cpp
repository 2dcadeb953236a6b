// The memory plan's census (device/memory_census.hpp): particles, boundary particles and non-empty
// cells per grid column, from the particles or from the lattice plan without building them.
#include "device/memory_census.hpp"

#include "device/memory_model.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace clsph::detail {

device::Grid grid_of(const Scene& scene) {
    // Lists kept over steps (run.list_buffer): cells wider by the buffer, so that tables built
    // before particles moved up to half of it still hold every pair within the support.
    const double support = scene.physics.support();
    return device::Grid(device::Box{scene.domain.min, scene.domain.max}, support * (1.0 + scene.run.list_buffer),
                        scene.domain.split_axis, scene.domain.periodic, device::reach_for(support, scene.physics.dp));
}

MemoryCensus census_of(const Scene& scene, const Particles& p) {
    const device::Grid grid = grid_of(scene);
    const std::uint32_t invalid = grid.params().invalid_key;
    MemoryCensus c;
    c.particles = p.size();
    c.per_column.assign(grid.params().n_s, 0);
    c.boundary_per_column.assign(grid.params().n_s, 0);
    c.cells_per_column.assign(grid.params().n_s, 0);
    std::vector<std::uint32_t> key(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        std::array<float, 3> off{};
        key[i] = grid.locate(p.position[i], off);
        if (key[i] != invalid) {
            const std::size_t col = grid.cell_of_key(key[i])[0];
            ++c.per_column[col];
            c.boundary_per_column[col] += p.type[i] != ParticleType::fluid;  // partition.cpp census()
        }
        if (p.type[i] == ParticleType::boundary) {
            c.any_boundary = true;
            c.max_boundary_id = std::max<std::uint32_t>(c.max_boundary_id, p.id[i]);
        }
    }
    key.erase(std::remove(key.begin(), key.end(), invalid), key.end());
    std::sort(key.begin(), key.end());
    key.erase(std::unique(key.begin(), key.end()), key.end());
    for (auto k : key) ++c.cells_per_column[grid.cell_of_key(k)[0]];
    return c;
}

MemoryCensus census_of(const Scene& scene, const scene::LatticePlan& plan) {
    // Per column, each piece's cells: the cells of its coordinates on the other two axes (a
    // boundary plane that is not a layer: its layer rows by every column and every row by its
    // layer columns). Removed fluid points are ignored (an upper bound by a few boundary cells).
    const device::Grid grid = grid_of(scene);
    const std::size_t columns = grid.params().n_s;
    MemoryCensus c;
    c.particles = static_cast<std::size_t>(plan.count());
    c.per_column.assign(columns, 0);
    c.boundary_per_column.assign(columns, 0);
    c.cells_per_column.assign(columns, 0);
    c.any_boundary = plan.boundary_count > 0;
    c.max_boundary_id = plan.boundary_count > 0 ? static_cast<std::uint32_t>(plan.boundary_count - 1) : 0;
    auto key_pos = [&](int axis) {
        for (int k = 0; k < 3; ++k)
            if (grid.axis(k) == axis) return k;
        return 0;
    };
    struct Parts {
        std::vector<std::uint32_t> all, layer;  // distinct key parts of the coordinates, of the layer ones
    };
    std::vector<std::array<Parts, 2>> parts(plan.pieces.size());
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> planes(plan.pieces.size());  // (plane, column)
    for (std::size_t k = 0; k < plan.pieces.size(); ++k) {
        const auto& piece = plan.pieces[k];
        for (int p = 1; p < 3; ++p) {
            const int kp = key_pos(piece.axis[p].axis);
            auto& out = parts[k][p - 1];
            for (std::size_t i = 0; i < piece.axis[p].size(); ++i) {
                std::uint32_t cell = 0;
                float off = 0.0f;
                if (!grid.locate_axis(kp, piece.axis[p].x[i], cell, off)) continue;
                out.all.push_back(grid.key_part(kp, cell));
                if (piece.fluid || piece.axis[p].layer[i]) out.layer.push_back(grid.key_part(kp, cell));
            }
            for (auto* v : {&out.all, &out.layer}) v->erase(std::unique(v->begin(), v->end()), v->end());
        }
        for (std::size_t i = 0; i < piece.axis[0].size(); ++i) {
            std::uint32_t col = 0;
            float off = 0.0f;
            if (!grid.locate_axis(0, piece.axis[0].x[i], col, off)) continue;
            c.per_column[col] += static_cast<std::size_t>(piece.plane_count[i]);
            if (!piece.fluid) c.boundary_per_column[col] += static_cast<std::size_t>(piece.plane_count[i]);
            planes[k].push_back({i, col});
        }
    }
    std::vector<std::vector<std::size_t>> in_column(columns);  // (piece, plane) pairs by column
    std::vector<std::uint32_t> keys;
    for (std::size_t col = 0; col < columns; ++col) {
        keys.clear();
        for (std::size_t k = 0; k < plan.pieces.size(); ++k) {
            const auto& piece = plan.pieces[k];
            bool full = false, partial = false;
            for (const auto& [plane, pc] : planes[k])
                if (pc == col && piece.plane_count[plane] > 0)
                    (piece.fluid || piece.axis[0].layer[plane] ? full : partial) = true;
            const auto& a = parts[k][0];
            const auto& b = parts[k][1];
            auto add = [&](const std::vector<std::uint32_t>& x, const std::vector<std::uint32_t>& y) {
                for (auto u : x)
                    for (auto v : y) keys.push_back(u | v);
            };
            if (full) add(a.all, b.all);
            if (partial && !full) {
                add(a.layer, b.all);
                add(a.all, b.layer);
            }
        }
        std::sort(keys.begin(), keys.end());
        c.cells_per_column[col] = static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
    }
    return c;
}

}  // namespace clsph::detail
