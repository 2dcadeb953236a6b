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
#include "grid.h"
#include "sph_kernel.h"

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

// The density of boundary particle i from its ghost node (see above).
inline float mdbc_density(const uint i, const uint cells, const GridParams g, const SphParams sp,
                          __global const float4* pos, __global const uint* cell_key, __global const uint* cell_start,
                          __global const float4* velrho, __global const uint* ids, const float3 mirror) {
    const float4 xb = pos[i];
    uint key;
    float3 off;
    if (!displace(g, pos_key(xb), xb.xyz, mirror, &key, &off)) return sp.rho0;
    const float4 xg = (float4)(off, as_float(key));
    float m[4][4] = {{0.0f}};
    float r[4] = {0.0f};
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
        }
    }
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
                            __global const uint* halt) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last || *halt != 0u) return;
    const uint id = ids[i];
    if ((id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) return;
    if (as_uint(pos[i].w) == g.invalid_key) return;
    const uint n = id & CLSPH_ID_MASK;
    const float3 mirror = n < ghost_count ? ghost[n].xyz : (float3)(0.0f);
    const uint k = counted ? count[0] : cells;
    velrho[i].w = mdbc_density(i, k, g, sp, pos, cell_key, cell_start, velrho, ids, mirror);
}

#ifdef CLSPH_LANES
// The CPU form (-DCLSPH_LANES=8|16; chosen where the interaction pass runs lanes, physics.cpp): a
// work-item per non-empty cell, the cell's owned boundary particles CLSPH_LANES at a time in the
// lanes of vector types (lanes.h). Their ghost nodes lie in nearby cells, not all in one: the lanes
// share the union of their neighbour rows (the box of their ghost nodes' cells, widened by the
// rows' reach), walked in the fine form's order (s, then a, then index), so each lane adds its own
// neighbours' terms in the order the fine form (mdbc_boundary) does; candidates outside a lane's
// support are masked. Each lane's 4x4 system is then solved as there. A batch whose rows would
// overlap themselves across a periodic wrap falls back to the fine form's function, lane by lane.
#include "lanes.h"

// The densities of boundary particles idx[0..n) (n >= 1) from their ghost nodes.
inline void mdbc_lanes_batch(const uint* idx, const uint n, const uint cells, const GridParams g, const SphParams sp,
                             __global const float4* pos, __global const uint* cell_key,
                             __global const uint* cell_start, __global float4* velrho, __global const uint* ids,
                             __global const float4* ghost, const uint ghost_count) {
    float3 mirror[VW];
    int ls[VW], la[VW], lb[VW], ok[VW];
    float lx[VW], ly[VW], lz[VW];
    int smin = 0, smax = -1, amin = 0, amax = -1, bmin = 0, bmax = -1, first_ok = -1;
    for (uint l = 0; l < n; ++l) {
        const uint i = idx[l];
        const uint m = ids[i] & CLSPH_ID_MASK;
        mirror[l] = m < ghost_count ? ghost[m].xyz : (float3)(0.0f);
        const float4 xb = pos[i];
        uint key;
        float3 off;
        ok[l] = displace(g, pos_key(xb), xb.xyz, mirror[l], &key, &off) ? -1 : 0;
        if (!ok[l]) continue;
        ls[l] = (int)key_s(g, key);
        la[l] = (int)key_a(g, key);
        lb[l] = (int)key_b(g, key);
        lx[l] = off.x;
        ly[l] = off.y;
        lz[l] = off.z;
        if (first_ok < 0) {
            first_ok = (int)l;
            smin = smax = ls[l];
            amin = amax = la[l];
            bmin = bmax = lb[l];
        } else {
            smin = min(smin, ls[l]);
            smax = max(smax, ls[l]);
            amin = min(amin, la[l]);
            amax = max(amax, la[l]);
            bmin = min(bmin, lb[l]);
            bmax = max(bmax, lb[l]);
        }
    }
    if (first_ok < 0) {  // no ghost node inside the domain
        for (uint l = 0; l < n; ++l) velrho[idx[l]].w = sp.rho0;
        return;
    }
    if (g.periodic_a && amax - amin + 2 * CLSPH_REACH + 1 > (int)g.n_a) {  // the rows would meet across the wrap
        for (uint l = 0; l < n; ++l)
            velrho[idx[l]].w = mdbc_density(idx[l], cells, g, sp, pos, cell_key, cell_start, velrho, ids, mirror[l]);
        return;
    }
    // Lanes without a ghost node in the domain, and those beyond n, copy the first that has one
    // (computed, never stored).
    for (uint l = 0; l < VW; ++l)
        if (l >= n || !ok[l]) {
            ls[l] = ls[first_ok];
            la[l] = la[first_ok];
            lb[l] = lb[first_ok];
            lx[l] = lx[first_ok];
            ly[l] = ly[first_ok];
            lz[l] = lz[first_ok];
        }
    const intV vs = vloadV(0, ls), va = vloadV(0, la), vb = vloadV(0, lb);
    const floatV ox = vloadV(0, lx), oy = vloadV(0, ly), oz = vloadV(0, lz);
    floatV m00 = 0.0f, m01 = 0.0f, m02 = 0.0f, m03 = 0.0f, m10 = 0.0f, m11 = 0.0f, m12 = 0.0f, m13 = 0.0f;
    floatV m20 = 0.0f, m21 = 0.0f, m22 = 0.0f, m23 = 0.0f, m30 = 0.0f, m31 = 0.0f, m32 = 0.0f, m33 = 0.0f;
    floatV r0 = 0.0f, r1 = 0.0f, r2s = 0.0f, r3 = 0.0f;
    for (int s2 = smin - 1; s2 <= smax + 1; ++s2) {
        if (s2 < 0 || s2 >= (int)g.n_s) continue;
        const floatV cs = convert_floatV(s2 - vs) * g.cell_s;
        for (int a_abs = amin - CLSPH_REACH; a_abs <= amax + CLSPH_REACH; ++a_abs) {
            int a2 = a_abs;
            if (g.periodic_a) {
                if (a2 < 0) a2 += (int)g.n_a;
                if (a2 >= (int)g.n_a) a2 -= (int)g.n_a;
            }
            if (a2 < 0 || a2 >= (int)g.n_a) continue;
            const floatV ca = convert_floatV(a_abs - va) * g.cell_a;
            const uint lo = make_key(g, (uint)s2, (uint)a2, (uint)bmin) - CLSPH_REACH;
            const uint hi = make_key(g, (uint)s2, (uint)a2, (uint)bmax) + CLSPH_REACH + 1u;
            const uint begin = cell_start[lower_bound_key(cell_key, cells, lo)];
            const uint end = cell_start[lower_bound_key(cell_key, cells, hi)];
            for (uint j = begin; j < end; ++j) {
                if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
                const float4 pj = pos[j];
                const floatV cb = convert_floatV((int)key_b(g, pos_key(pj)) - vb) * g.cell_b;
                floatV cd[3];
                cd[AXIS_S] = cs;
                cd[AXIS_A] = ca;
                cd[AXIS_B] = cb;
                const floatV dx = cd[0] + (pj.x - ox), dy = cd[1] + (pj.y - oy), dz = cd[2] + (pj.z - oz);
                const floatV rr = dx * dx + dy * dy + dz * dz;
                const intV hit = rr < sp.support2;
                if (!any(hit)) continue;
                const floatV rad = sqrt(rr);
                const float rho = velrho[j].w;
                const float v = sp.mass / rho;
                const floatV w = select((floatV)(0.0f), v * kernel_w_lanes(&sp, rad), hit);
                const floatV f = select((floatV)(0.0f), (-v * kernel_f_lanes(&sp, rad)) * sp.h, hit & (rr > 0.0f));
                const floatV qx = dx * sp.inv_h, qy = dy * sp.inv_h, qz = dz * sp.inv_h;
                const floatV gx = f * dx, gy = f * dy, gz = f * dz;
                const float drho = rho - sp.rho0;
                m00 += w;
                m01 += w * qx;
                m02 += w * qy;
                m03 += w * qz;
                m10 += gx;
                m11 += gx * qx;
                m12 += gx * qy;
                m13 += gx * qz;
                m20 += gy;
                m21 += gy * qx;
                m22 += gy * qy;
                m23 += gy * qz;
                m30 += gz;
                m31 += gz * qx;
                m32 += gz * qy;
                m33 += gz * qz;
                r0 += w * drho;
                r1 += gx * drho;
                r2s += gy * drho;
                r3 += gz * drho;
            }
        }
    }
    float acc[20][VW];
    vstoreV(m00, 0, acc[0]);
    vstoreV(m01, 0, acc[1]);
    vstoreV(m02, 0, acc[2]);
    vstoreV(m03, 0, acc[3]);
    vstoreV(m10, 0, acc[4]);
    vstoreV(m11, 0, acc[5]);
    vstoreV(m12, 0, acc[6]);
    vstoreV(m13, 0, acc[7]);
    vstoreV(m20, 0, acc[8]);
    vstoreV(m21, 0, acc[9]);
    vstoreV(m22, 0, acc[10]);
    vstoreV(m23, 0, acc[11]);
    vstoreV(m30, 0, acc[12]);
    vstoreV(m31, 0, acc[13]);
    vstoreV(m32, 0, acc[14]);
    vstoreV(m33, 0, acc[15]);
    vstoreV(r0, 0, acc[16]);
    vstoreV(r1, 0, acc[17]);
    vstoreV(r2s, 0, acc[18]);
    vstoreV(r3, 0, acc[19]);
    for (uint l = 0; l < n; ++l) {
        float m[4][4], r[4];
        for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = acc[k][l];
        for (int k = 0; k < 4; ++k) r[k] = acc[16 + k][l];
        velrho[idx[l]].w = ok[l] ? mdbc_solve(sp, m, r, mirror[l]) : sp.rho0;
    }
}

// Owned boundary particles [first, last), a work-item per non-empty cell (launched with
// work-groups of one; `cells` or count[0] as mdbc_boundary's, the launch may be the tables'
// capacity).
__kernel void mdbc_boundary_lanes(const uint first, const uint last, const uint cells, __global const uint* count,
                                  const uint counted, const GridParams g, const SphParams sp,
                                  __global const float4* pos, __global const uint* cell_key,
                                  __global const uint* cell_start, __global float4* velrho, __global const uint* ids,
                                  __global const float4* ghost, const uint ghost_count, __global const uint* halt) {
    const uint c = (uint)get_global_id(0);
    const uint k = counted ? count[0] : cells;
    if (c >= k || *halt != 0u) return;
    const uint begin = max(cell_start[c], first), end = min(cell_start[c + 1u], last);
    uint idx[VW];
    uint n = 0;
    for (uint i = begin; i < end; ++i) {
        if ((ids[i] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) continue;
        if (as_uint(pos[i].w) == g.invalid_key) continue;
        idx[n++] = i;
        if (n == VW) {
            mdbc_lanes_batch(idx, n, k, g, sp, pos, cell_key, cell_start, velrho, ids, ghost, ghost_count);
            n = 0;
        }
    }
    if (n > 0) mdbc_lanes_batch(idx, n, k, g, sp, pos, cell_key, cell_start, velrho, ids, ghost, ghost_count);
}
#endif
