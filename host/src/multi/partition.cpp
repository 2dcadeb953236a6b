#include "multi/partition.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <array>

namespace clsph::multi {

std::uint32_t Partition::column_key(std::size_t column) const {
    const auto& g = grid_.params();
    if (column >= g.n_s) return g.invalid_key;
    if (g.shift_s >= 32) return 0;
    return static_cast<std::uint32_t>(column) << g.shift_s;
}

device::KeyRange Partition::keys_of(const Need& need) const {
    if (need.empty()) return {0, 0};
    return {column_key(need.lo), column_key(need.hi)};
}

std::vector<Need> Partition::needs(const std::vector<Slab>& slabs) const {
    std::vector<Need> need(slabs.size());
    for (std::size_t e = 0; e < slabs.size(); ++e) {
        const Slab& s = slabs[e];
        if (s.empty()) continue;
        need[e] = {s.first_col > 0 ? s.first_col - 1 : 0, s.first_col, s.end_col, std::min(s.end_col + 1, columns())};
    }
    return need;
}

std::size_t Partition::owner_of(std::uint32_t key, const std::vector<Slab>& slabs) const {
    const std::size_t c = column_of(key);
    for (std::size_t d = 0; d < slabs.size(); ++d)
        if (c >= slabs[d].first_col && c < slabs[d].end_col) return d;
    return slabs.size() - 1;
}

std::vector<std::size_t> Partition::cuts(const std::vector<Slab>& slabs) {
    std::vector<std::size_t> c;
    for (const auto& s : slabs) c.push_back(s.first_col);
    c.push_back(slabs.back().end_col);
    return c;
}

void Partition::set_cuts(std::vector<Slab>& slabs, const std::vector<std::size_t>& c) const {
    if (c.size() != slabs.size() + 1 || c.front() != 0 || c.back() != columns() || !std::is_sorted(c.begin(), c.end()))
        throw Error("cuts must be devices + 1 non-decreasing columns from 0 to the column count");
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        slabs[d].first_col = c[d];
        slabs[d].end_col = c[d + 1];
    }
}

Census Partition::census(const Particles& p) {
    const std::size_t n_col = columns();
    const std::uint32_t invalid = grid_.params().invalid_key;
    Census c;
    c.key.resize(p.size());
    c.profile.work.assign(n_col, 0.0);
    c.profile.particles.assign(n_col, 0);
    c.boundary.assign(n_col, 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        std::array<float, 3> off{};
        c.key[i] = grid_.locate(p.position[i], off);
        if (c.key[i] == invalid) continue;
        const std::size_t col = column_of(c.key[i]);
        const bool fluid = p.type[i] == ParticleType::fluid;
        c.profile.work[col] += fluid ? 1.0 : balance::default_boundary_weight;
        c.profile.particles[col] += 1;
        c.boundary[col] += !fluid;
    }
    boundary_per_column_ = c.boundary;
    return c;
}

std::vector<Particles> Partition::split(const Particles& p, const Census& census, const std::vector<Slab>& slabs) const {
    std::vector<Particles> out(slabs.size());
    const std::uint32_t invalid = grid_.params().invalid_key;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t d = census.key[i] == invalid ? 0 : owner_of(census.key[i], slabs);
        out[d].push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    }
    return out;
}

balance::ColumnProfile Partition::column_profile(const std::vector<Slab>& slabs) const {
    // The sorted keys put each column in one contiguous range, so its count is a difference of two
    // column positions. Boundary particles never move, so the fluid count is the rest.
    balance::ColumnProfile p;
    p.work.assign(columns(), 0.0);
    p.particles.assign(columns(), 0);
    for (const auto& s : slabs) {
        if (s.empty() || !s.columns_known() || s.columns_first != s.first_col || s.columns_end != s.end_col) continue;
        for (std::size_t c = s.first_col; c < s.end_col; ++c) {
            const std::size_t n = s.column_at[c - s.first_col + 1] - s.column_at[c - s.first_col];
            const std::size_t b = std::min<std::size_t>(n, boundary_per_column_[c]);
            p.particles[c] = n;
            p.work[c] = balance::column_work(n - b, b);
        }
    }
    return p;
}

}  // namespace clsph::multi
