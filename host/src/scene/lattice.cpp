#include "scene/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace clsph::scene {

std::int64_t lattice_first(double min, double dp) { return static_cast<std::int64_t>(std::ceil(min / dp - 1e-9)); }
std::int64_t lattice_last(double max, double dp) { return static_cast<std::int64_t>(std::floor(max / dp + 1e-9)); }

void sample_walls(const BoxWalls& w, double dp, std::vector<Vec3>& out) {
    // Per axis, the coordinates a wall particle may take: the layers outside a selected min face
    // (min - l dp), the lattice from min towards max (min + i dp), and the layers of a selected max
    // face (max + l dp), so that each face's layers sit at offsets 0, dp, 2dp from it exactly even
    // when the box is not a whole number of dp long. A point is a wall particle when one of its
    // coordinates is in a selected face's layers.
    std::array<std::vector<double>, 3> coord;
    std::array<std::vector<char>, 3> is_wall;
    for (int a = 0; a < 3; ++a) {
        const bool lo_face = w.faces & (1u << (2 * a)), hi_face = w.faces & (1u << (2 * a + 1));
        const double span = w.max[a] - w.min[a];
        const auto n = static_cast<std::int64_t>(std::floor(span / dp + 1e-9));
        if (lo_face)
            for (int l = w.layers - 1; l >= 1; --l) coord[a].push_back(w.min[a] - l * dp), is_wall[a].push_back(1);
        for (std::int64_t i = 0; i <= n; ++i) {
            const double c = w.min[a] + static_cast<double>(i) * dp;
            if (hi_face && c > w.max[a] - 1e-9 * dp) break;  // the max face's own layer follows
            coord[a].push_back(c);
            is_wall[a].push_back(lo_face && i == 0);
        }
        if (hi_face)
            for (int l = 0; l < w.layers; ++l) coord[a].push_back(w.max[a] + l * dp), is_wall[a].push_back(1);
    }
    for (std::size_t i = 0; i < coord[0].size(); ++i)
        for (std::size_t j = 0; j < coord[1].size(); ++j)
            for (std::size_t k = 0; k < coord[2].size(); ++k)
                if (is_wall[0][i] || is_wall[1][j] || is_wall[2][k])
                    out.push_back({coord[0][i], coord[1][j], coord[2][k]});
}

void sample_solid(const SolidBox& b, double dp, std::vector<Vec3>& out) {
    std::array<std::int64_t, 3> n{};
    for (int k = 0; k < 3; ++k) n[k] = static_cast<std::int64_t>(std::floor((b.max[k] - b.min[k]) / dp + 1e-9));
    for (std::int64_t i = 0; i <= n[0]; ++i)
        for (std::int64_t j = 0; j <= n[1]; ++j)
            for (std::int64_t k = 0; k <= n[2]; ++k) {
                const std::int64_t depth = std::min({i, j, k, n[0] - i, n[1] - j, n[2] - k});
                if (b.layers > 0 && depth >= b.layers) continue;
                out.push_back({b.min[0] + static_cast<double>(i) * dp, b.min[1] + static_cast<double>(j) * dp,
                               b.min[2] + static_cast<double>(k) * dp});
            }
}

PointHash::PointHash(const std::vector<Vec3>& points, double cell) : cell_(cell) {
    std::vector<std::uint64_t> k(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        k[i] = key(static_cast<std::int64_t>(std::floor(points[i][0] / cell)),
                   static_cast<std::int64_t>(std::floor(points[i][1] / cell)),
                   static_cast<std::int64_t>(std::floor(points[i][2] / cell)));
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return k[a] < k[b]; });
    keys_.reserve(points.size());
    points_.reserve(points.size());
    for (auto i : order) {
        keys_.push_back(k[i]);
        points_.push_back(points[i]);
    }
}

std::uint64_t PointHash::key(std::int64_t i, std::int64_t j, std::int64_t k) const {
    // 21 bits per axis, offset so negative indices fit: lattices of up to 2 million cells per axis.
    const auto f = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffffu; };
    return (f(i) << 42) | (f(j) << 21) | f(k);
}

bool PointHash::any_within(const Vec3& x, double r) const {
    const std::int64_t reach = static_cast<std::int64_t>(std::ceil(r / cell_));
    const std::int64_t ci = static_cast<std::int64_t>(std::floor(x[0] / cell_));
    const std::int64_t cj = static_cast<std::int64_t>(std::floor(x[1] / cell_));
    const std::int64_t ck = static_cast<std::int64_t>(std::floor(x[2] / cell_));
    const double r2 = r * r;
    for (std::int64_t i = ci - reach; i <= ci + reach; ++i)
        for (std::int64_t j = cj - reach; j <= cj + reach; ++j)
            for (std::int64_t k = ck - reach; k <= ck + reach; ++k) {
                const auto kk = key(i, j, k);
                auto it = std::lower_bound(keys_.begin(), keys_.end(), kk);
                for (; it != keys_.end() && *it == kk; ++it) {
                    const auto& p = points_[static_cast<std::size_t>(it - keys_.begin())];
                    const double dx = p[0] - x[0], dy = p[1] - x[1], dz = p[2] - x[2];
                    if (dx * dx + dy * dy + dz * dz < r2) return true;
                }
            }
    return false;
}

FootprintIndex::FootprintIndex(const std::vector<FluidBlock>& blocks, double pad) {
    if (blocks.empty()) return;
    double lo[2] = {blocks[0].min[0] - pad, blocks[0].min[1] - pad}, hi[2] = {blocks[0].max[0] + pad, blocks[0].max[1] + pad};
    for (const auto& b : blocks)
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], b.min[a] - pad), hi[a] = std::max(hi[a], b.max[a] + pad);
    origin_[0] = lo[0];
    origin_[1] = lo[1];
    // Cells as small as the pad, coarsened until the grid and the entries stay bounded (at most
    // 4 M cells and 32 M entries), whatever the blocks' sizes and number.
    cell_ = std::max({pad, (hi[0] - lo[0]) * 1e-6, (hi[1] - lo[1]) * 1e-6, 1e-12});
    auto span = [&](double a, double b, int axis, std::size_t& first, std::size_t& last) {
        first = static_cast<std::size_t>(std::max(0.0, std::floor((a - lo[axis]) / cell_)));
        last = static_cast<std::size_t>(std::max(0.0, std::floor((b - lo[axis]) / cell_)));
    };
    for (;;) {
        nx_ = static_cast<std::size_t>(std::floor((hi[0] - lo[0]) / cell_)) + 1;
        ny_ = static_cast<std::size_t>(std::floor((hi[1] - lo[1]) / cell_)) + 1;
        if (static_cast<double>(nx_) * static_cast<double>(ny_) <= 4.0e6) {
            double entries = 0;
            for (const auto& b : blocks) {
                std::size_t x0, x1, y0, y1;
                span(b.min[0] - pad, b.max[0] + pad, 0, x0, x1);
                span(b.min[1] - pad, b.max[1] + pad, 1, y0, y1);
                entries += static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1);
            }
            if (entries <= 3.2e7) break;
        }
        cell_ *= 2.0;
    }
    starts_.assign(nx_ * ny_ + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::size_t> fill;
        if (pass == 1) {
            for (std::size_t c = 0; c < nx_ * ny_; ++c) starts_[c + 1] += starts_[c];
            entries_.resize(starts_.back());
            fill.assign(starts_.begin(), starts_.end() - 1);
        }
        for (std::size_t i = 0; i < blocks.size(); ++i) {
            std::size_t x0, x1, y0, y1;
            span(blocks[i].min[0] - pad, blocks[i].max[0] + pad, 0, x0, x1);
            span(blocks[i].min[1] - pad, blocks[i].max[1] + pad, 1, y0, y1);
            for (std::size_t y = y0; y <= y1 && y < ny_; ++y)
                for (std::size_t x = x0; x <= x1 && x < nx_; ++x) {
                    const std::size_t c = y * nx_ + x;
                    if (pass == 0)
                        ++starts_[c + 1];
                    else
                        entries_[fill[c]++] = i;
                }
        }
    }
}

}  // namespace clsph::scene
