// Modified dynamic boundary conditions (mDBC; English, Dominguez, Vacondio, Crespo, Stansby, Lind,
// Chiapponi & Gomez-Gesteira 2021): a boundary particle b takes its density from a ghost node G
// mirrored into the fluid (G = x_b + ghost[id_b].xyz, host/src/scene/ghost_nodes.cpp), by a
// first-order corrected kernel interpolation over fluid particles j only (Liu & Liu 2006):
//   A [rho_G, h grad rho_G]^T = [sum V_j W (rho_j - rho0), sum V_j h grad_G W (rho_j - rho0)]^T
//   A = [ sum V W        sum V W q^T        ]    q = (x_j - x_G) / h,  V_j = m / rho_j
//       [ sum V h grad W  sum V h grad W q^T ]   grad_G W = F(r) (x_G - x_j)
// so that a density varying linearly (a hydrostatic column) is reproduced exactly; then
//   rho_b = rho0 + rho_G + grad rho_G . (x_b - x_G)         where |det A| >= CLSPH_MDBC_DET (shared.h),
//   rho_b = rho0 + sum V W (rho_j - rho0) / sum V W           (Shepard) where the matrix is ill-
//                                                             conditioned but fluid is near,
//   rho_b = rho0                                              without fluid near G,
// and never below rho0 (as with DBC, a wall does not pull the fluid in). A is dimensionless (q and
// h grad W), close to the identity for a full support, so the threshold does not depend on dp.
// G may lie a few cells from b (5 dp for a third layer): its neighbours are found from G's own cell
// through the cell tables (binary search per row), not from b's neighbour rows.
//
// The pass runs after the force pass of a step and writes the owned boundary particles' densities
// in place (it reads only fluid densities): the forces of the next step use them, and every device
// that holds b as a ghost gets the owner's value at the next exchange, so results do not depend on
// the device count.
//
// -DCLSPH_NOSLIP (no-slip walls, boundaries.slip "no-slip"; English et al. 2021, DualSPHysics'
// mDBC SlipMode 2): the same sums with the fluid's velocities on the right-hand side give the
// fluid's velocity at the ghost node,
//   A [v_G, h grad v_G]^T = [sum V_j W v_j, sum V_j h grad_G W v_j]^T     (each component)
// of which only the value at G is kept: v_G (Shepard, sum V W v / sum V W, where the density takes
// Shepard). The velocity is mirrored about the wall's at the node rather than extrapolated, so the
// wall's velocity holds halfway between b and G, on the boundary interface. The pass writes
// v_wall - v_G, v_wall = velrho[b].xyz (the wall's own: 0 at rest, the motion's or the body's
// from motion.cl), into the xyz of b's entry of the force pass's output `wall_seen` (its w, b's
// drho/dt, is kept); 0 where no fluid is near G. The interaction passes then see b moving at
// velrho[b].xyz + that: wall_velocity.h says why it lives there and not in velrho.
#include "grid.h"
#include "sph_kernel.h"

#ifdef CLSPH_NOSLIP
#define WALL_OUT , float3 *wall_offset
#define WALL_ARGS , __global float4 *wall_seen
#define WALL_ARG , wall_seen
#else
#define WALL_OUT
#define WALL_ARGS
#define WALL_ARG
#endif

// The cell and offset of x + d (x given by its key and offset); false when it leaves the domain.
inline bool displace(const GridParams g, const uint key, const float3 off, const float3 d, uint* key_out,
                     float3* off_out) {
    float3 o = off + d;
    int s = (int)key_s(g, key), a = (int)key_a(g, key), b = (int)key_b(g, key);
    const int ds = (int)rint(COMP(o, AXIS_S) / g.cell_s);
    const int da = (int)rint(COMP(o, AXIS_A) / g.cell_a);
    const int db = (int)rint(COMP(o, AXIS_B) / g.cell_b);
    COMP(o, AXIS_S) -= (float)ds * g.cell_s;
    COMP(o, AXIS_A) -= (float)da * g.cell_a;
    COMP(o, AXIS_B) -= (float)db * g.cell_b;
    s += ds;
    a += da;
    b += db;
    if (g.periodic_a) {
        if (a < 0) a += (int)g.n_a;
        if (a >= (int)g.n_a) a -= (int)g.n_a;
    }
    if (s < 0 || s >= (int)g.n_s || a < 0 || a >= (int)g.n_a || b < 0 || b >= (int)g.n_b) return false;
    *key_out = make_key(g, (uint)s, (uint)a, (uint)b);
    *off_out = o;
    return true;
}

// Solves the 4x4 system m x = r in place (Gaussian elimination, partial pivoting); returns det m.
inline float solve4(float m[4][4], float r[4]) {
    float det = 1.0f;
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int k = c + 1; k < 4; ++k)
            if (fabs(m[k][c]) > fabs(m[p][c])) p = k;
        if (p != c) {
            for (int k = 0; k < 4; ++k) {
                const float t = m[c][k];
                m[c][k] = m[p][k];
                m[p][k] = t;
            }
            const float t = r[c];
            r[c] = r[p];
            r[p] = t;
            det = -det;
        }
        const float piv = m[c][c];
        det *= piv;
        if (piv == 0.0f) return 0.0f;
        for (int k = c + 1; k < 4; ++k) {
            const float f = m[k][c] / piv;
            for (int l = c; l < 4; ++l) m[k][l] -= f * m[c][l];
            r[k] -= f * r[c];
        }
    }
    for (int c = 3; c >= 0; --c) {
        float v = r[c];
        for (int l = c + 1; l < 4; ++l) v -= m[c][l] * r[l];
        r[c] = v / m[c][c];
    }
    return det;
}

// The boundary particle's density from the sums m, r over its ghost node's fluid neighbours
// (see above; m and r are overwritten).
inline float mdbc_solve(const SphParams sp, float m[4][4], float r[4], const float3 mirror) {
    const float sum_w = m[0][0], shepard = r[0];
    if (!(sum_w > 0.0f)) return sp.rho0;
    const float det = solve4(m, r);
    float rho;
    if (fabs(det) >= CLSPH_MDBC_DET) {
        const float3 to_b = -mirror * sp.inv_h;  // (x_b - x_G) / h: r[1..3] is h grad rho
        rho = sp.rho0 + r[0] + r[1] * to_b.x + r[2] * to_b.y + r[3] * to_b.z;
    } else {
        rho = sp.rho0 + shepard / sum_w;
    }
    return fmax(rho, sp.rho0);
}

#ifdef CLSPH_NOSLIP
// The fluid's velocity at the ghost node from the sums m (overwritten) and u (each row of r for
// the three components at once): first order where |det m| >= CLSPH_MDBC_DET, as mdbc_solve
// decides for the density, else Shepard; only called with fluid near the node (m[0][0] > 0).
inline float3 ghost_velocity(float m[4][4], float3 u[4]) {
    const float3 shepard = u[0] / m[0][0];
    float det = 1.0f;
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int k = c + 1; k < 4; ++k)
            if (fabs(m[k][c]) > fabs(m[p][c])) p = k;
        if (p != c) {
            for (int k = 0; k < 4; ++k) {
                const float t = m[c][k];
                m[c][k] = m[p][k];
                m[p][k] = t;
            }
            const float3 t = u[c];
            u[c] = u[p];
            u[p] = t;
            det = -det;
        }
        const float piv = m[c][c];
        det *= piv;
        if (piv == 0.0f) return shepard;
        for (int k = c + 1; k < 4; ++k) {
            const float f = m[k][c] / piv;
            for (int l = c; l < 4; ++l) m[k][l] -= f * m[c][l];
            u[k] -= f * u[c];
        }
    }
    if (!(fabs(det) >= CLSPH_MDBC_DET)) return shepard;
    for (int c = 3; c >= 0; --c) {
        float3 v = u[c];
        for (int l = c + 1; l < 4; ++l) v -= m[c][l] * u[l];
        u[c] = v / m[c][c];
    }
    return u[0];
}

// v_wall - v_G for a boundary particle whose wall moves at v_wall, from its node's sums (m is
// overwritten): 0 without fluid near the node.
inline float3 wall_offset_of(float m[4][4], float3 u[4], const float3 v_wall) {
    if (!(m[0][0] > 0.0f)) return (float3)(0.0f);
    return v_wall - ghost_velocity(m, u);
}

// Writes b's offset into the xyz of its entry of the force pass's output, keeping w (drho/dt).
inline void store_wall_offset(__global float4* wall_seen, const uint i, const float3 d) {
    float4 o = wall_seen[i];
    o.xyz = d;
    wall_seen[i] = o;
}
#endif

// The density of boundary particle i from its ghost node (see above).
inline float mdbc_density(const uint i, const uint cells, const GridParams g, const SphParams sp,
                          __global const float4* pos, __global const uint* cell_key, __global const uint* cell_start,
                          __global const float4* velrho, __global const uint* ids,
                          const float3 mirror WALL_OUT) {
    const float4 xb = pos[i];
    uint key;
    float3 off;
#ifdef CLSPH_NOSLIP
    *wall_offset = (float3)(0.0f);
#endif
    if (!displace(g, pos_key(xb), xb.xyz, mirror, &key, &off)) return sp.rho0;
    const float4 xg = (float4)(off, as_float(key));
    float m[4][4] = {{0.0f}};
    float r[4] = {0.0f};
#ifdef CLSPH_NOSLIP
    float3 u[4] = {(float3)(0.0f), (float3)(0.0f), (float3)(0.0f), (float3)(0.0f)};
#endif
    const int s = (int)key_s(g, key), a = (int)key_a(g, key);
    const uint b = key_b(g, key);
    for (uint row = 0; row < ROWS; ++row) {
        uint begin, end;
        if (!row_of_point(g, cells, cell_key, cell_start, s, a, b, row, &begin, &end)) continue;
        for (uint j = begin; j < end; ++j) {
            if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
            const float4 pj = pos[j];
            const float3 d = relative_position(g, key, xg, pos_key(pj), pj);  // x_j - x_G
            const float r2 = dot(d, d);
            if (r2 >= sp.support2) continue;
            const float rad = sqrt(r2);
            const float rho = velrho[j].w;
            const float v = sp.mass / rho;
            const float w = v * kernel_w(&sp, rad);
            const float3 q = d * sp.inv_h;
            const float3 gw = (-v * kernel_f(&sp, rad) * sp.h) * d;  // V h grad_G W
            const float drho = rho - sp.rho0;
            m[0][0] += w;
            m[0][1] += w * q.x;
            m[0][2] += w * q.y;
            m[0][3] += w * q.z;
            m[1][0] += gw.x;
            m[1][1] += gw.x * q.x;
            m[1][2] += gw.x * q.y;
            m[1][3] += gw.x * q.z;
            m[2][0] += gw.y;
            m[2][1] += gw.y * q.x;
            m[2][2] += gw.y * q.y;
            m[2][3] += gw.y * q.z;
            m[3][0] += gw.z;
            m[3][1] += gw.z * q.x;
            m[3][2] += gw.z * q.y;
            m[3][3] += gw.z * q.z;
            r[0] += w * drho;
            r[1] += gw.x * drho;
            r[2] += gw.y * drho;
            r[3] += gw.z * drho;
#ifdef CLSPH_NOSLIP
            const float3 vj = velrho[j].xyz;
            u[0] += w * vj;
            u[1] += gw.x * vj;
            u[2] += gw.y * vj;
            u[3] += gw.z * vj;
#endif
        }
    }
#ifdef CLSPH_NOSLIP
    float mv[4][4];
    for (int k = 0; k < 16; ++k) mv[k / 4][k % 4] = m[k / 4][k % 4];
    *wall_offset = wall_offset_of(mv, u, velrho[i].xyz);
#endif
    return mdbc_solve(sp, m, r, mirror);
}

// Owned boundary particles [first, last): their densities from their ghost nodes. `ghost` holds
// each boundary particle's offset to its ghost node by id (ghost_count entries; ids beyond it, and
// zero offsets, interpolate at the particle itself). The number of non-empty cells is `cells`, or
// count[0] when counted != 0 (the step ahead: the tables' count stays on the device).
__kernel void mdbc_boundary(const uint first, const uint last, const uint cells, __global const uint* count,
                            const uint counted, const GridParams g, const SphParams sp, __global const float4* pos,
                            __global const uint* cell_key, __global const uint* cell_start, __global float4* velrho,
                            __global const uint* ids, __global const float4* ghost, const uint ghost_count,
                            __global const uint* halt WALL_ARGS) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last || *halt != 0u) return;
    const uint id = ids[i];
    if ((id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) return;
    if (as_uint(pos[i].w) == g.invalid_key) return;
    const uint n = id & CLSPH_ID_MASK;
    const float3 mirror = n < ghost_count ? ghost[n].xyz : (float3)(0.0f);
    const uint k = counted ? count[0] : cells;
#ifdef CLSPH_NOSLIP
    float3 d;
    const float rho = mdbc_density(i, k, g, sp, pos, cell_key, cell_start, velrho, ids, mirror, &d);
    store_wall_offset(wall_seen, i, d);
    velrho[i].w = rho;
#else
    velrho[i].w = mdbc_density(i, k, g, sp, pos, cell_key, cell_start, velrho, ids, mirror);
#endif
}
