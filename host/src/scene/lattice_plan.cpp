#include "scene/lattice_plan.hpp"

#include "clsph/error.hpp"
#include "scene/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace clsph::scene {

const std::int64_t kNearLimit = [] {
    const double r = std::ldexp(1.0, kFixedBits) * (1.0 - 1e-6);
    return static_cast<std::int64_t>(std::floor(r * r));
}();

namespace {

std::string vec(const Vec3& v) {
    std::ostringstream o;
    o << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
    return o.str();
}

// Box walls on one axis: the layers outside a selected min face, the lattice from min towards
// max, the layers of a selected max face (the same coordinates sample_walls() takes).
void walls_axis(const BoxWalls& w, double dp, int a, LatticeAxis& out) {
    const bool lo_face = w.faces & (1u << (2 * a)), hi_face = w.faces & (1u << (2 * a + 1));
    const auto n = static_cast<std::int64_t>(std::floor((w.max[a] - w.min[a]) / dp + 1e-9));
    if (lo_face)
        for (int l = w.layers - 1; l >= 1; --l) out.x.push_back(w.min[a] - l * dp), out.layer.push_back(1);
    for (std::int64_t i = 0; i <= n; ++i) {
        const double c = w.min[a] + static_cast<double>(i) * dp;
        if (hi_face && c > w.max[a] - 1e-9 * dp) break;
        out.x.push_back(c);
        out.layer.push_back(lo_face && i == 0);
    }
    if (hi_face)
        for (int l = 0; l < w.layers; ++l) out.x.push_back(w.max[a] + l * dp), out.layer.push_back(1);
}

// A solid box on one axis: kept within `layers` of either face (every coordinate when filled).
void solid_axis(const SolidBox& b, double dp, int a, LatticeAxis& out) {
    const auto n = static_cast<std::int64_t>(std::floor((b.max[a] - b.min[a]) / dp + 1e-9));
    for (std::int64_t i = 0; i <= n; ++i) {
        out.x.push_back(b.min[a] + static_cast<double>(i) * dp);
        out.layer.push_back(b.layers <= 0 || std::min(i, n - i) < b.layers);
    }
}

void fluid_axis(const FluidBlock& f, double dp, int a, LatticeAxis& out) {
    for (std::int64_t i = lattice_first(f.min[a], dp), e = lattice_last(f.max[a], dp); i <= e; ++i)
        out.x.push_back(static_cast<double>(i) * dp);
}

std::int64_t squared_capped(std::int64_t d) {
    d = d < 0 ? -d : d;
    if (d >= (std::int64_t{1} << (kFixedBits + 1))) return kNearLimit;
    return std::min(d * d, kNearLimit);
}

// For each value of `from`: the capped squared distance to the nearest value of `sorted`.
std::vector<std::int64_t> nearest(const std::vector<std::int64_t>& from, const std::vector<std::int64_t>& sorted) {
    std::vector<std::int64_t> out(from.size(), kNearLimit);
    if (sorted.empty()) return out;
    for (std::size_t i = 0; i < from.size(); ++i) {
        const auto it = std::lower_bound(sorted.begin(), sorted.end(), from[i]);
        std::int64_t best = kNearLimit;
        if (it != sorted.end()) best = std::min(best, squared_capped(*it - from[i]));
        if (it != sorted.begin()) best = std::min(best, squared_capped(*std::prev(it) - from[i]));
        out[i] = best;
    }
    return out;
}

}  // namespace

int resolved_split_axis(const Domain& d) {
    if (d.split_axis >= 0) return d.split_axis;
    int s = 0;
    for (int k = 1; k < 3; ++k)
        if (d.max[k] - d.min[k] > d.max[s] - d.min[s]) s = k;
    return s;
}

int LatticePiece::pos_of_axis(int a) const {
    for (int p = 0; p < 3; ++p)
        if (axis[p].axis == a) return p;
    return 0;
}

bool LatticePiece::removed(std::size_t i0, std::size_t i1, std::size_t i2) const {
    const std::size_t i[3] = {i0, i1, i2};
    for (const auto& t : near)
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            if (t.layer[a][i[a]] + t.any[b][i[b]] + t.any[c][i[c]] < kNearLimit) return true;
        }
    return false;
}

std::size_t LatticePiece::block_of(std::size_t i0, std::size_t i1, std::size_t i2, std::size_t blocks) const {
    const std::uint64_t m = mask[0][i0] & mask[1][i1] & mask[2][i2];
    if (m == 0) return blocks;
    std::size_t b = 0;
    while (!((m >> b) & 1u)) ++b;
    return b;
}

bool LatticePlan::supports(const Scene& scene) { return scene.meshes.empty() && scene.fluids.size() <= 64; }

LatticePlan LatticePlan::make(const Scene& scene) {
    scene.validate();
    if (!supports(scene)) throw Error("LatticePlan: the scene has meshes or more than 64 fluid blocks");
    const auto& ph = scene.physics;
    const double dp = ph.dp, rho0 = ph.rho0, gamma = ph.gamma, c0 = scene.sound_speed();
    const double B = c0 * c0 * rho0 / gamma;
    const double weight = rho0 * -ph.gravity[2];  // pressure per metre of depth
    const double reach = ph.support();
    LatticePlan plan;
    plan.split_axis = resolved_split_axis(scene.domain);
    plan.blocks = scene.fluids.size();
    const int order[3] = {plan.split_axis, plan.split_axis == 0 ? 1 : 0, plan.split_axis == 2 ? 1 : 2};
    const std::size_t nb = plan.blocks;
    auto density_of = [&](double p) { return static_cast<float>(rho0 * std::pow(1.0 + p / B, 1.0 / gamma)); };

    // A piece of each wall, box and block: its axes by loop position, then its fixed-point coordinates.
    auto add_piece = [&](bool fluid, std::size_t source, const auto& axis_of) {
        LatticePiece piece;
        piece.fluid = fluid;
        piece.source = source;
        for (int p = 0; p < 3; ++p) {
            auto& ax = piece.axis[p];
            ax.axis = order[p];
            axis_of(order[p], ax);
            ax.q.resize(ax.size());
            for (std::size_t i = 0; i < ax.size(); ++i) {
                const double q = ax.x[i] / dp * std::ldexp(1.0, kFixedBits);
                if (!(std::abs(q) < 1e18))
                    throw SceneError("physics.dp: a coordinate of " + std::to_string(ax.x[i]) + " m is beyond 1e12 dp from the origin");
                ax.q[i] = std::llround(q);
            }
            if (ax.layer.size() != ax.size()) ax.layer.assign(ax.size(), 0);
        }
        plan.pieces.push_back(std::move(piece));
    };
    for (std::size_t w = 0; w < scene.walls.size(); ++w)
        add_piece(false, w, [&](int a, LatticeAxis& ax) { walls_axis(scene.walls[w], dp, a, ax); });
    for (std::size_t b = 0; b < scene.solids.size(); ++b)
        add_piece(false, b, [&](int a, LatticeAxis& ax) { solid_axis(scene.solids[b], dp, a, ax); });
    const std::size_t n_boundary = plan.pieces.size();
    for (std::size_t f = 0; f < scene.fluids.size(); ++f)
        add_piece(true, f, [&](int a, LatticeAxis& ax) { fluid_axis(scene.fluids[f], dp, a, ax); });

    // Boundary pieces: points per plane, and the block whose pressure each point takes.
    std::vector<std::size_t> rank(nb);
    for (std::size_t b = 0; b < nb; ++b) rank[b] = b;
    auto surface = [&](std::size_t b) { return scene.fluids[b].surface.value_or(scene.fluids[b].max[2]); };
    std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
        return weight >= 0 ? surface(a) > surface(b) : surface(a) < surface(b);
    });
    for (std::size_t k = 0; k < n_boundary; ++k) {
        auto& piece = plan.pieces[k];
        const auto& a0 = piece.axis[0];
        const std::uint64_t n1 = piece.axis[1].size(), n2 = piece.axis[2].size();
        std::uint64_t l1 = 0, l2 = 0;
        for (auto v : piece.axis[1].layer) l1 += v;
        for (auto v : piece.axis[2].layer) l2 += v;
        piece.plane_count.resize(a0.size());
        for (std::size_t i = 0; i < a0.size(); ++i)
            piece.plane_count[i] = a0.layer[i] ? n1 * n2 : l1 * n2 + (n1 - l1) * l2;
        for (int p = 0; p < 3; ++p) {
            const auto& ax = piece.axis[p];
            piece.mask[p].assign(ax.size(), ~std::uint64_t{0});
            if (ax.axis == 2) continue;
            for (std::size_t i = 0; i < ax.size(); ++i) {
                std::uint64_t m = 0;
                for (std::size_t r = 0; r < nb; ++r) {
                    const auto& f = scene.fluids[rank[r]];
                    if (ax.x[i] >= f.min[ax.axis] - reach && ax.x[i] <= f.max[ax.axis] + reach) m |= std::uint64_t{1} << r;
                }
                piece.mask[p][i] = m;
            }
        }
        const auto& z = piece.axis[piece.pos_of_axis(2)];
        piece.density.resize((nb + 1) * z.size());
        piece.pressure.resize((nb + 1) * z.size());
        for (std::size_t r = 0; r <= nb; ++r)
            for (std::size_t iz = 0; iz < z.size(); ++iz) {
                double p = 0.0;
                if (r < nb) p = std::max(p, weight * (surface(rank[r]) - z.x[iz]));
                piece.density[r * z.size() + iz] = density_of(p);
                piece.pressure[r * z.size() + iz] = static_cast<float>(p);
            }
    }

    // Fluid pieces: the boundary pieces near them, the points kept per plane, and the block each
    // point belongs to.
    for (std::size_t k = n_boundary; k < plan.pieces.size(); ++k) {
        auto& piece = plan.pieces[k];
        for (std::size_t bk = 0; bk < n_boundary; ++bk) {
            const auto& bp = plan.pieces[bk];
            NearTable t;
            t.boundary = bk;
            bool any_near = true, layer_near = false;
            for (int p = 0; p < 3; ++p) {
                std::vector<std::int64_t> layer_q;
                for (std::size_t i = 0; i < bp.axis[p].size(); ++i)
                    if (bp.axis[p].layer[i]) layer_q.push_back(bp.axis[p].q[i]);
                t.layer[p] = nearest(piece.axis[p].q, layer_q);
                t.any[p] = nearest(piece.axis[p].q, bp.axis[p].q);
                any_near = any_near && std::any_of(t.any[p].begin(), t.any[p].end(), [](auto v) { return v < kNearLimit; });
                layer_near = layer_near || std::any_of(t.layer[p].begin(), t.layer[p].end(), [](auto v) { return v < kNearLimit; });
            }
            if (any_near && layer_near) piece.near.push_back(std::move(t));
        }
        // Removed points per plane: each is a candidate (every term below the limit) of the
        // combination (table, axis) that removes it; it is counted at its first such candidacy.
        const std::size_t n0 = piece.axis[0].size(), n1 = piece.axis[1].size(), n2 = piece.axis[2].size();
        std::vector<std::uint64_t> removed(n0, 0);
        auto below = [](const std::vector<std::int64_t>& v) {
            std::vector<std::size_t> out;
            for (std::size_t i = 0; i < v.size(); ++i)
                if (v[i] < kNearLimit) out.push_back(i);
            return out;
        };
        auto candidate = [&](std::size_t t, int a, const std::size_t* i) {
            const auto& tb = piece.near[t];
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            return tb.layer[a][i[a]] < kNearLimit && tb.any[b][i[b]] < kNearLimit && tb.any[c][i[c]] < kNearLimit;
        };
        for (std::size_t t = 0; t < piece.near.size(); ++t)
            for (int a = 0; a < 3; ++a) {
                const int b = (a + 1) % 3, c = (a + 2) % 3;
                const auto sa = below(piece.near[t].layer[a]), sb = below(piece.near[t].any[b]), sc = below(piece.near[t].any[c]);
                for (auto ia : sa)
                    for (auto ib : sb)
                        for (auto ic : sc) {
                            std::size_t i[3];
                            i[a] = ia, i[b] = ib, i[c] = ic;
                            bool earlier = false;
                            for (std::size_t t2 = 0; t2 <= t && !earlier; ++t2)
                                for (int a2 = 0; a2 < (t2 == t ? a : 3) && !earlier; ++a2) earlier = candidate(t2, a2, i);
                            if (!earlier && piece.removed(i[0], i[1], i[2])) ++removed[i[0]];
                        }
            }
        piece.plane_count.resize(n0);
        for (std::size_t i = 0; i < n0; ++i) piece.plane_count[i] = std::uint64_t{n1} * n2 - removed[i];

        for (int p = 0; p < 3; ++p) {
            const auto& ax = piece.axis[p];
            piece.mask[p].assign(ax.size(), 0);
            for (std::size_t i = 0; i < ax.size(); ++i)
                for (std::size_t b = 0; b < nb; ++b) {
                    const auto& f = scene.fluids[b];
                    if (ax.x[i] >= f.min[ax.axis] - 1e-9 && ax.x[i] <= f.max[ax.axis] + 1e-9) piece.mask[p][i] |= std::uint64_t{1} << b;
                }
        }
        const auto& z = piece.axis[piece.pos_of_axis(2)];
        piece.density.resize((nb + 1) * z.size());
        piece.pressure.resize((nb + 1) * z.size());
        for (std::size_t b = 0; b <= nb; ++b)
            for (std::size_t iz = 0; iz < z.size(); ++iz) {
                const double top = b < nb ? surface(b) : z.x[iz];
                const double p = std::max(0.0, weight * (top - z.x[iz]));
                piece.density[b * z.size() + iz] = density_of(p);
                piece.pressure[b * z.size() + iz] = static_cast<float>(p);
            }
        piece.velocity.assign(nb + 1, {0.0f, 0.0f, 0.0f});
        for (std::size_t b = 0; b < nb; ++b)
            for (int a = 0; a < 3; ++a) piece.velocity[b][a] = static_cast<float>(scene.fluids[b].velocity[a]);
    }

    std::uint64_t next = 0;
    for (auto& piece : plan.pieces) {
        piece.first_id = next;
        piece.count = 0;
        for (auto c : piece.plane_count) piece.count += c;
        next += piece.count;
        (piece.fluid ? plan.fluid_count : plan.boundary_count) += piece.count;
        if (piece.fluid && piece.count == 0) {
            const auto& f = scene.fluids[piece.source];
            if (piece.points_per_plane() * piece.axis[0].size() == 0)
                throw SceneError("fluid[" + std::to_string(piece.source) + "]: the block " + vec(f.min) + " - " + vec(f.max) +
                                 " holds no lattice point at physics.dp = " + std::to_string(scene.physics.dp) +
                                 " m (it is thinner than dp on some axis): make physics.dp smaller or the block larger");
            throw SceneError("fluid[" + std::to_string(piece.source) + "]: no fluid particle is left in the block " +
                             vec(f.min) + " - " + vec(f.max) + ": each of its " +
                             std::to_string(piece.points_per_plane() * piece.axis[0].size()) +
                             " lattice points is within dp of a boundary particle (it lies inside or against a solid box, "
                             "a wall or a mesh)");
        }
    }
    if (plan.fluid_count == 0)
        throw SceneError("fluid: the scene has no fluid particle at physics.dp = " + std::to_string(scene.physics.dp) +
                         " m: make physics.dp smaller or the fluid blocks larger");
    if (plan.count() > (std::uint64_t{1} << 31) - 1)
        throw SceneError("physics.dp: the scene has " + std::to_string(plan.count()) +
                         " particles, more than the 2^31 - 1 that 31-bit ids allow; enlarge dp");
    return plan;
}

Particles LatticePlan::particles(const std::function<bool(const LatticePiece&, std::size_t)>& keep_plane,
                                 bool boundary_only) const {
    Particles out;
    for (const auto& piece : pieces) {
        if (boundary_only && piece.fluid) break;
        const auto type = piece.fluid ? ParticleType::fluid : ParticleType::boundary;
        const std::size_t n0 = piece.axis[0].size(), n1 = piece.axis[1].size(), n2 = piece.axis[2].size();
        const int pz = piece.pos_of_axis(2);
        const std::size_t nz = piece.axis[pz].size();
        std::uint64_t id = piece.first_id;
        for (std::size_t i0 = 0; i0 < n0; ++i0) {
            if (!keep_plane(piece, i0)) {
                id += piece.plane_count[i0];
                continue;
            }
            for (std::size_t i1 = 0; i1 < n1; ++i1)
                for (std::size_t i2 = 0; i2 < n2; ++i2) {
                    const std::size_t i[3] = {i0, i1, i2};
                    if (piece.fluid ? piece.removed(i0, i1, i2)
                                    : !(piece.axis[0].layer[i0] || piece.axis[1].layer[i1] || piece.axis[2].layer[i2]))
                        continue;
                    Vec3 x{};
                    for (int p = 0; p < 3; ++p) x[piece.axis[p].axis] = piece.axis[p].x[i[p]];
                    const std::size_t row = piece.block_of(i0, i1, i2, blocks);
                    const std::size_t t = row * nz + i[pz];
                    const auto v = piece.fluid ? piece.velocity[row] : std::array<float, 3>{0.0f, 0.0f, 0.0f};
                    out.push_back(static_cast<std::uint32_t>(id++), type, x, v, piece.density[t], piece.pressure[t]);
                }
        }
    }
    return out;
}

}  // namespace clsph::scene
