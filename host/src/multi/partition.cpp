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
        need[e] = {s.first_col > halo_ ? s.first_col - halo_ : 0, s.first_col, s.end_col,
                   std::min(s.end_col + halo_, columns())};
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

void Partition::set_cuts(std::vector<Slab>& slabs, const std::vector<std::size_t>& wanted) const {
    if (wanted.size() != slabs.size() + 1 || wanted.front() != 0 || wanted.back() != columns() ||
        !std::is_sorted(wanted.begin(), wanted.end()))
        throw Error("cuts must be devices + 1 non-decreasing columns from 0 to the column count");
    std::vector<std::size_t> c = wanted;
    if (!cut_allowed_.empty()) {
        // Forced cuts (tests, the off and static modes, a checkpoint's) may land where a cut may
        // not: the nearest allowed column, nearer the start on a tie; 0 and the end always are.
        for (std::size_t k = 1; k + 1 < c.size(); ++k) {
            std::size_t at = c[k];
            for (std::size_t r = 0; !cut_allowed_[at]; ++r) {
                if (c[k] >= r && cut_allowed_[c[k] - r]) at = c[k] - r;
                else if (c[k] + r <= columns() && cut_allowed_[c[k] + r]) at = c[k] + r;
            }
            c[k] = std::max(at, c[k - 1]);
        }
    }
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
    c.profile.cut_allowed = cut_allowed_;
    return c;
}

Census Partition::census(const scene::LatticePlan& plan) {
    const std::size_t n_col = columns();
    Census c;
    c.profile.work.assign(n_col, 0.0);
    c.profile.particles.assign(n_col, 0);
    c.boundary.assign(n_col, 0);
    for (const auto& piece : plan.pieces)
        for (std::size_t i = 0; i < piece.axis[0].size(); ++i) {
            std::uint32_t col = 0;
            float off = 0.0f;
            if (!grid_.locate_axis(0, piece.axis[0].x[i], col, off)) continue;
            const auto n = static_cast<std::size_t>(piece.plane_count[i]);
            c.profile.work[col] += static_cast<double>(n) * (piece.fluid ? 1.0 : balance::default_boundary_weight);
            c.profile.particles[col] += n;
            if (!piece.fluid) c.boundary[col] += n;
        }
    boundary_per_column_ = c.boundary;
    c.profile.cut_allowed = cut_allowed_;
    return c;
}

void Partition::restrict_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets,
                              double support) {
    fixed_allowed_ = allowed_cuts(p, ghost_offsets, support, 0);
    cut_allowed_ = fixed_allowed_;
}

void Partition::restrict_body_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets,
                                   double support, std::size_t margin) {
    cut_allowed_ = allowed_cuts(p, ghost_offsets, support, margin);
    for (std::size_t k = 0; k < fixed_allowed_.size() && k < cut_allowed_.size(); ++k)
        cut_allowed_[k] = cut_allowed_[k] && fixed_allowed_[k];
}

std::vector<char> Partition::allowed_cuts(const Particles& p, const std::vector<std::array<float, 3>>& ghost_offsets,
                                          double support, std::size_t margin) const {
    const std::size_t n_col = columns();
    const int s_axis = grid_.axis(0);
    const auto& dom = grid_.domain();
    const std::uint32_t invalid = grid_.params().invalid_key;
    // Per column, the lowest and highest column any of its boundary particles needs.
    std::vector<std::size_t> lo(n_col), hi(n_col);
    for (std::size_t c = 0; c < n_col; ++c) lo[c] = hi[c] = c;
    auto column_at = [&](std::array<double, 3> x) {  // beyond the domain on another axis: its column still
        for (int k = 0; k < 3; ++k) x[k] = std::clamp(x[k], dom.lo[k], dom.hi[k]);
        std::array<float, 3> off{};
        const std::uint32_t key = grid_.locate(x, off);
        return key == invalid ? std::size_t{0} : column_of(key);
    };
    std::size_t reach = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::boundary) continue;
        std::array<float, 3> off{};
        const std::uint32_t key = grid_.locate(p.position[i], off);
        if (key == invalid) continue;
        const std::size_t c = column_of(key);
        auto g = p.position[i];
        for (int k = 0; k < 3; ++k) g[k] += ghost_offsets[i][k];
        auto below = g, above = g;
        below[s_axis] -= support;
        above[s_axis] += support;
        // With a margin (a body that moves before the pass), in any column within it of c, and
        // needing as much further.
        const std::size_t need_lo = column_at(below), need_hi = column_at(above);
        for (std::size_t m = c > margin ? c - margin : 0; m <= std::min(n_col - 1, c + margin); ++m) {
            lo[m] = std::min(lo[m], need_lo > margin ? need_lo - margin : 0);
            hi[m] = std::max(hi[m], std::min(n_col - 1, need_hi + margin));
            reach = std::max({reach, m - lo[m], hi[m] - m});
        }
    }
    // A cut before column k: the slab after it holds from column k - 1, the one before it up to k.
    std::vector<char> allowed(n_col + 1, 1);
    for (std::size_t k = 1; k < n_col; ++k) {
        const std::size_t from = k > reach + 1 ? k - reach - 1 : 0, to = std::min(n_col, k + reach + 1);
        for (std::size_t c = from; c < to && allowed[k]; ++c)
            if ((c >= k && lo[c] + 1 < k) || (c < k && hi[c] > k)) allowed[k] = 0;
    }
    return allowed;
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
    p.cut_allowed = cut_allowed_;
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
