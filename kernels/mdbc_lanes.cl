// mDBC's CPU form (-DCLSPH_LANES=8|16; chosen where the interaction pass runs lanes, physics.cpp): a
// work-item per non-empty cell, the cell's owned boundary particles CLSPH_LANES at a time in the
// lanes of vector types (lanes.h). Their ghost nodes lie in nearby cells, not all in one: the lanes
// share the union of their neighbour rows (the box of their ghost nodes' cells, widened by the
// rows' reach), walked in the fine form's order (s, then a, then index), so each lane adds its own
// neighbours' terms in the order the fine form (mdbc_boundary) does; candidates outside a lane's
// support are masked. Each lane's 4x4 system is then solved as there. A batch whose rows would
// overlap themselves across a periodic wrap falls back to the fine form's function, lane by lane.
// -DCLSPH_NOSLIP: each lane also sums the fluid's velocities and gets its v_wall - v_G as mdbc.cl.
#include "mdbc.cl"
#include "lanes.h"

// The densities of boundary particles idx[0..n) (n >= 1) from their ghost nodes.
inline void mdbc_lanes_batch(const uint* idx, const uint n, const uint cells, const GridParams g, const SphParams sp,
                             __global const float4* pos, __global const uint* cell_key,
                             __global const uint* cell_start, __global float4* velrho, __global const uint* ids,
                             __global const float4* ghost, const uint ghost_count WALL_ARGS) {
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
        for (uint l = 0; l < n; ++l) {
            velrho[idx[l]].w = sp.rho0;
#ifdef CLSPH_NOSLIP
            store_wall_offset(wall_seen, idx[l], (float3)(0.0f));
#endif
        }
        return;
    }
    if (g.periodic_a && amax - amin + 2 * CLSPH_REACH + 1 > (int)g.n_a) {  // the rows would meet across the wrap
        for (uint l = 0; l < n; ++l) {
#ifdef CLSPH_NOSLIP
            float3 d;
            const float rho = mdbc_density(idx[l], cells, g, sp, pos, cell_key, cell_start, velrho, ids, mirror[l], &d);
            store_wall_offset(wall_seen, idx[l], d);
            velrho[idx[l]].w = rho;
#else
            velrho[idx[l]].w = mdbc_density(idx[l], cells, g, sp, pos, cell_key, cell_start, velrho, ids, mirror[l]);
#endif
        }
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
#ifdef CLSPH_NOSLIP
    floatV u0x = 0.0f, u0y = 0.0f, u0z = 0.0f, u1x = 0.0f, u1y = 0.0f, u1z = 0.0f;
    floatV u2x = 0.0f, u2y = 0.0f, u2z = 0.0f, u3x = 0.0f, u3y = 0.0f, u3z = 0.0f;
#endif
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
#ifdef CLSPH_NOSLIP
                const float3 vj = velrho[j].xyz;
                u0x += w * vj.x;
                u0y += w * vj.y;
                u0z += w * vj.z;
                u1x += gx * vj.x;
                u1y += gx * vj.y;
                u1z += gx * vj.z;
                u2x += gy * vj.x;
                u2y += gy * vj.y;
                u2z += gy * vj.z;
                u3x += gz * vj.x;
                u3y += gz * vj.y;
                u3z += gz * vj.z;
#endif
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
#ifdef CLSPH_NOSLIP
    float vel[12][VW];
    vstoreV(u0x, 0, vel[0]);
    vstoreV(u0y, 0, vel[1]);
    vstoreV(u0z, 0, vel[2]);
    vstoreV(u1x, 0, vel[3]);
    vstoreV(u1y, 0, vel[4]);
    vstoreV(u1z, 0, vel[5]);
    vstoreV(u2x, 0, vel[6]);
    vstoreV(u2y, 0, vel[7]);
    vstoreV(u2z, 0, vel[8]);
    vstoreV(u3x, 0, vel[9]);
    vstoreV(u3y, 0, vel[10]);
    vstoreV(u3z, 0, vel[11]);
#endif
    for (uint l = 0; l < n; ++l) {
        float m[4][4], r[4];
        for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = acc[k][l];
        for (int k = 0; k < 4; ++k) r[k] = acc[16 + k][l];
#ifdef CLSPH_NOSLIP
        float3 u[4];
        for (int k = 0; k < 4; ++k) u[k] = (float3)(vel[3 * k][l], vel[3 * k + 1][l], vel[3 * k + 2][l]);
        store_wall_offset(wall_seen, idx[l], ok[l] ? wall_offset_of(m, u, velrho[idx[l]].xyz) : (float3)(0.0f));
        for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = acc[k][l];  // wall_offset_of overwrote it
#endif
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
                                  __global const float4* ghost, const uint ghost_count, __global const uint* halt
                                      WALL_ARGS) {
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
            mdbc_lanes_batch(idx, n, k, g, sp, pos, cell_key, cell_start, velrho, ids, ghost, ghost_count WALL_ARG);
            n = 0;
        }
    }
    if (n > 0) mdbc_lanes_batch(idx, n, k, g, sp, pos, cell_key, cell_start, velrho, ids, ghost, ghost_count WALL_ARG);
}
