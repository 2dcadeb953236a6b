// The mDBC density of a boundary particle computed in plain C++ double from every fluid particle
// (brute force): the reference of kernels/mdbc.cl that test_mdbc and test_motion compare with; and
// the fluid's velocity at its ghost node, which no-slip walls mirror (test_mdbc_noslip).
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "support/sph_reference.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace clsph::test {

// Solves the 4x4 system in double (Gaussian elimination, partial pivoting); returns det.
inline double solve4(double m[4][4], double r[4]) {
    double det = 1;
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int k = c + 1; k < 4; ++k)
            if (std::abs(m[k][c]) > std::abs(m[p][c])) p = k;
        if (p != c) {
            for (int k = 0; k < 4; ++k) std::swap(m[c][k], m[p][k]);
            std::swap(r[c], r[p]);
            det = -det;
        }
        det *= m[c][c];
        if (m[c][c] == 0) return 0;
        for (int k = c + 1; k < 4; ++k) {
            const double f = m[k][c] / m[c][c];
            for (int l = c; l < 4; ++l) m[k][l] -= f * m[c][l];
            r[k] -= f * r[c];
        }
    }
    for (int c = 3; c >= 0; --c) {
        double v = r[c];
        for (int l = c + 1; l < 4; ++l) v -= m[c][l] * r[l];
        r[c] = v / m[c][c];
    }
    return det;
}

struct Reference {
    double rho = 0;
    double det = 0;  // of the correction matrix (0 without fluid)
};

// The mDBC density of a boundary particle at xb with ghost offset `mirror`, from every fluid
// particle of `p` (brute force, double): docs/scenes.md, boundaries.method.
inline Reference reference_density(const Particles& p, const Scene& s, const SphParams& sp, const Vec3& xb,
                            const std::array<float, 3>& mirror) {
    const double h = s.physics.h(), support = s.physics.support(), rho0 = s.physics.rho0;
    const Vec3 g{xb[0] + mirror[0], xb[1] + mirror[1], xb[2] + mirror[2]};
    double m[4][4] = {}, r[4] = {};
    for (std::size_t j = 0; j < p.size(); ++j) {
        if (p.type[j] != ParticleType::fluid) continue;
        const double d[3] = {p.position[j][0] - g[0], p.position[j][1] - g[1], p.position[j][2] - g[2]};
        const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (r2 >= support * support) continue;
        const double rad = std::sqrt(r2), rho = p.density[j], v = sp.mass / rho;
        const double w = v * test::reference_w(s.physics.kernel, h, rad);
        const double f = test::reference_f(s.physics.kernel, h, rad);
        double row[4] = {w, 0, 0, 0}, q[4] = {1, d[0] / h, d[1] / h, d[2] / h};
        for (int k = 0; k < 3; ++k) row[k + 1] = -v * f * h * d[k];
        for (int a = 0; a < 4; ++a) {
            for (int b = 0; b < 4; ++b) m[a][b] += row[a] * q[b];
            r[a] += row[a] * (rho - rho0);
        }
    }
    Reference out;
    const double sum_w = m[0][0], shepard = r[0];
    if (!(sum_w > 0)) {
        out.rho = rho0;
        return out;
    }
    out.det = solve4(m, r);
    if (std::abs(out.det) >= CLSPH_MDBC_DET)
        out.rho = rho0 + r[0] - (r[1] * mirror[0] + r[2] * mirror[1] + r[3] * mirror[2]) / h;
    else
        out.rho = rho0 + shepard / sum_w;
    out.rho = std::max(out.rho, rho0);
    return out;
}

struct VelocityReference {
    std::array<double, 3> v{0, 0, 0};  // the fluid's velocity at the ghost node
    double det = 0;                    // of the correction matrix (0 without fluid)
    bool fluid = false;                // any fluid within the node's support
};

// The fluid's velocity at the ghost node of a boundary particle at xb (offset `mirror`), from every
// fluid particle of `p` (brute force, double): first order where |det| >= CLSPH_MDBC_DET, else
// Shepard (docs/scenes.md, boundaries.slip).
inline VelocityReference reference_ghost_velocity(const Particles& p, const Scene& s, const SphParams& sp,
                                                  const Vec3& xb, const std::array<float, 3>& mirror) {
    const double h = s.physics.h(), support = s.physics.support();
    const Vec3 g{xb[0] + mirror[0], xb[1] + mirror[1], xb[2] + mirror[2]};
    double m[4][4] = {}, u[3][4] = {};
    for (std::size_t j = 0; j < p.size(); ++j) {
        if (p.type[j] != ParticleType::fluid) continue;
        const double d[3] = {p.position[j][0] - g[0], p.position[j][1] - g[1], p.position[j][2] - g[2]};
        const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (r2 >= support * support) continue;
        const double rad = std::sqrt(r2), v = sp.mass / p.density[j];
        const double f = test::reference_f(s.physics.kernel, h, rad);
        double row[4] = {v * test::reference_w(s.physics.kernel, h, rad), 0, 0, 0}, q[4] = {1, d[0] / h, d[1] / h, d[2] / h};
        for (int k = 0; k < 3; ++k) row[k + 1] = -v * f * h * d[k];
        for (int a = 0; a < 4; ++a) {
            for (int b = 0; b < 4; ++b) m[a][b] += row[a] * q[b];
            for (int c = 0; c < 3; ++c) u[c][a] += row[a] * p.velocity[j][static_cast<std::size_t>(c)];
        }
    }
    VelocityReference out;
    const double sum_w = m[0][0];
    if (!(sum_w > 0)) return out;
    out.fluid = true;
    for (int c = 0; c < 3; ++c) {
        double mc[4][4], r[4];
        for (int a = 0; a < 4; ++a) {
            r[a] = u[c][a];
            for (int b = 0; b < 4; ++b) mc[a][b] = m[a][b];
        }
        out.det = solve4(mc, r);
        out.v[static_cast<std::size_t>(c)] = std::abs(out.det) >= CLSPH_MDBC_DET ? r[0] : u[c][0] / sum_w;
    }
    return out;
}

}  // namespace clsph::test
