// WCSPH interactions on the shared neighbour loop (neighbour_loop.h), one pass:
//   continuity   drho_i/dt = sum_j m v_ij . grad_i W_ij                          (all particles)
//   diffusion    + delta h c0 sum_j psi_ij F'_ij m / rho_j,  F'_ij = -F >= 0
//                Molteni & Colagrossi (2009): psi_ij = 2 (rho_j - rho_i), every pair;
//                Fourtakas et al. (2019):     psi_ij = 2 (rho_j - rho_i - rho^H_ji), fluid-fluid
//                pairs only, rho^H_ji = rho0^2 g.(x_j - x_i) / (gamma B) (the hydrostatic density
//                difference, linearised: |rho0 g dz / B| < 1e-3 within a kernel support)
//   pressure     a_i = -sum_j m (p_i + p_j) / (rho_i rho_j) grad_i W_ij              (fluid i)
//   viscosity    Monaghan (1992): Pi_ij = -alpha c0 mu_ij / rho_mean, mu = h v_ij.x_ij / (r^2 + eta^2),
//                when v_ij.x_ij < 0; alpha between fluid particles, alpha_wall between a fluid
//                particle and a boundary particle (at rest: wall friction; 0 by default)
//   laminar      -DCLSPH_VISCOSITY=1 instead of Monaghan's: Morris et al. (1997) in the form of
//                Lo & Shao (2002), a_i += sum_j m 4 nu (x_ij . grad_i W_ij) / ((rho_i + rho_j)
//                (r^2 + eta^2)) v_ij, between fluid particles and with boundary particles alike
//                (walls: no-slip at the velocity they show, wall_velocity.h)
//   SPS          -DCLSPH_VISCOSITY=2: laminar plus the sub-particle-scale stress of sps.cl (its pass
//                before this one), a_i += sum_j m (tau_i / rho_i^2 + tau_j / rho_j^2) . grad_i W_ij
//                (boundary particles' tau is 0)
//   gravity      added to fluid accelerations
// Dynamic boundary particles (DBC, Crespo et al. 2007) get only drho/dt: they do not move.
// -DCLSPH_SUMMATION: fluid densities come from the summation pass (density.cl), so fluid drho = 0.
// -DCLSPH_DIFFUSION=0|1|2: none, Molteni-Colagrossi, Fourtakas.
// -DCLSPH_MDBC: boundary particles take their density from ghost nodes (mdbc.cl), not from the
// continuity equation: their drho/dt is 0 and the fine form skips them.
// -DCLSPH_NOSLIP (with -DCLSPH_MDBC): a boundary neighbour's velocity in every term above is the
// fluid's at its ghost node mirrored about the wall's, 2 v_wall - v_G (wall_velocity.h).
#include "sph_kernel.h"
#include "wall_velocity.h"

#ifndef CLSPH_DIFFUSION
#define CLSPH_DIFFUSION 2
#endif
#ifndef CLSPH_VISCOSITY
#define CLSPH_VISCOSITY 0
#endif

typedef struct {
    float4 pos;
    float4 velrho;
    uint fluid;
#if CLSPH_VISCOSITY == 2
    float4 ta, tb;  // tau / rho^2 of sps.cl: (xx, xy, xz, yy), (yz, zz, 0, 0)
#endif
} ForceNeighbour;

#if CLSPH_VISCOSITY == 2
#define SPS_ARGS , __global const float4 *tau
#define LOAD_SPS(nb, j)              \
    do {                             \
        (nb).ta = tau[2u * (j)];     \
        (nb).tb = tau[2u * (j) + 1u]; \
    } while (0)
// m (tau_i + tau_j) . F d (grad_i W = F (x_i - x_j)), the tensors symmetric.
inline float3 sps_term(const float4 a, const float4 b, const float3 fr) {
    return (float3)(a.x * fr.x + a.y * fr.y + a.z * fr.z, a.y * fr.x + a.w * fr.y + b.x * fr.z,
                    a.z * fr.x + b.x * fr.y + b.y * fr.z);
}
#else
#define SPS_ARGS
#define LOAD_SPS(nb, j) \
    do {                \
    } while (0)
#endif

typedef struct {
    float3 acc;
    float drho;
    float p, rho;
    uint fluid;
} ForceState;

#define INTERACTION_NAME forces
#define INTERACTION_ARGS                                                                                    \
    , const SphParams sp, __global const float4 *velrho, __global const uint *ids, __global float4 *accel SPS_ARGS \
        NOSLIP_ARGS
#define NEIGHBOUR_T ForceNeighbour
#define LOAD_NEIGHBOUR(nb, j)                                                   \
    do {                                                                        \
        (nb).velrho = SEEN_VELRHO(j);                                           \
        (nb).fluid = (ids[j] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;          \
        LOAD_SPS(nb, j);                                                        \
    } while (0)
#define STATE_T ForceState
#define STATE_INIT(st, i, self)                      \
    do {                                             \
        (st).acc = (float3)(0.0f);                   \
        (st).drho = 0.0f;                            \
        (st).rho = (self).velrho.w;                  \
        (st).p = pressure_of(&sp, (st).rho);         \
        (st).fluid = (self).fluid;                   \
    } while (0)

// Adds the terms of one pair (i, j) within the support to i's sums. The pressure of j is computed
// only where it is used (fluid i): a third of the pairs at SPHERIC-2 belong to boundary particles.
inline void force_pair(ForceState* st, const SphParams* sp, const ForceNeighbour* self, const ForceNeighbour* nb,
                       const float3 rij, const float r2) {
    if (r2 <= 1e-18f) return;  // the particle itself
#if CLSPH_DIFFUSION != 1
    // Two boundary particles: both at rest (DBC walls do not move), so v_ij = 0 and every term is
    // zero; without Molteni-Colagrossi diffusion (which compares their densities) nothing to add.
    if (!st->fluid && !nb->fluid) return;
#endif
    const float r = sqrt(r2);
    const float f = kernel_f(sp, r);
    const float3 d = -rij;  // x_i - x_j
    const float3 vij = self->velrho.xyz - nb->velrho.xyz;
    const float vd = dot(vij, d);
    const float rho_j = nb->velrho.w;
    const float m = sp->mass;
#ifndef CLSPH_SUMMATION
    st->drho += m * vd * f;
#else
    if (!st->fluid) st->drho += m * vd * f;
#endif
#if CLSPH_DIFFUSION == 1
    st->drho += sp->diffusion * 2.0f * (rho_j - st->rho) * (-f) * m / rho_j;
#elif CLSPH_DIFFUSION == 2
    if (st->fluid && nb->fluid) {
        const float rho_h = sp->hydro * (sp->gx * rij.x + sp->gy * rij.y + sp->gz * rij.z);
        st->drho += sp->diffusion * 2.0f * (rho_j - st->rho - rho_h) * (-f) * m / rho_j;
    }
#endif
    if (st->fluid) {
        const float p_j = pressure_of(sp, rho_j);
        float coef = (st->p + p_j) / (st->rho * rho_j);
#if CLSPH_VISCOSITY == 0
        if (vd < 0.0f) {
            const float mu = sp->h * vd / (r2 + sp->eta2);
            coef += -(nb->fluid ? sp->visc_alpha : sp->visc_alpha_wall) * sp->c0 * mu / (0.5f * (st->rho + rho_j));
        }
        st->acc += (-m * coef * f) * d;
#else
        st->acc += (-m * coef * f) * d;
        st->acc += (m * sp->visc_laminar * f * r2 / ((st->rho + rho_j) * (r2 + sp->eta2))) * vij;
#endif
#if CLSPH_VISCOSITY == 2
        st->acc += m * sps_term(self->ta + nb->ta, self->tb + nb->tb, f * d);
#endif
    }
}

#define PAIR(st, self, nb, i, j, rij, r2) force_pair(&(st), &sp, &(self), &(nb), (rij), (r2))
#ifdef CLSPH_MDBC
#define BOUNDARY_DRHO(drho) 0.0f
#define SKIP_PARTICLE(self) (((ids[i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID))
#define STORE_SKIPPED(i) accel[i] = (float4)(0.0f)
#else
#define BOUNDARY_DRHO(drho) (drho)
#endif
#define STATE_STORE(st, i)                                                                      \
    do {                                                                                        \
        float4 out = (float4)(0.0f, 0.0f, 0.0f, BOUNDARY_DRHO((st).drho));                      \
        if ((st).fluid) out = (float4)((st).acc + (float3)(sp.gx, sp.gy, sp.gz), (st).drho);    \
        accel[i] = out;                                                                         \
    } while (0)

#ifdef CLSPH_LANES
// The CPU form (neighbour_loop.h, lanes): force_pair for CLSPH_LANES particles i of one cell at
// once against one neighbour j. Lanes without a hit (and i itself) get F = 0, which zeroes every
// term (each is proportional to F); boundary lanes' accelerations are summed and never stored.
#include "lanes.h"

typedef struct {
    floatV vx, vy, vz, rho, p;
    intV fluid;  // -1 in fluid lanes
    floatV ax, ay, az, drho;
#if CLSPH_VISCOSITY == 2
    floatV txx, txy, txz, tyy, tyz, tzz;  // tau_i / rho_i^2
#endif
} ForceLanes;

inline void force_lanes(ForceLanes* st, const SphParams* sp, const float4 vr_j, const uint id_j, const floatV rx,
                        const floatV ry, const floatV rz, const floatV r2, const intV hit SPS_ARGS, const uint j) {
    const bool fluid_j = (id_j >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;
    const floatV r = sqrt(r2);
    const floatV mf = select((floatV)(0.0f), sp->mass * kernel_f_lanes(sp, r), hit & (r2 > 1e-18f));
    const floatV vx = st->vx - vr_j.x, vy = st->vy - vr_j.y, vz = st->vz - vr_j.z;
    const floatV vd = -(vx * rx + vy * ry + vz * rz);  // v_ij . (x_i - x_j)
    const float rho_j = vr_j.w;
#ifndef CLSPH_SUMMATION
    st->drho += mf * vd;
#else
    st->drho += select(mf * vd, (floatV)(0.0f), st->fluid);
#endif
#if CLSPH_DIFFUSION == 1
    st->drho += (sp->diffusion * 2.0f / rho_j) * (rho_j - st->rho) * (-mf);
#elif CLSPH_DIFFUSION == 2
    if (fluid_j) {
        const floatV rho_h = sp->hydro * (sp->gx * rx + sp->gy * ry + sp->gz * rz);
        st->drho += select((floatV)(0.0f), (sp->diffusion * 2.0f / rho_j) * (rho_j - st->rho - rho_h) * (-mf), st->fluid);
    }
#endif
    const float p_j = pressure_of(sp, rho_j);
    floatV coef = (st->p + p_j) / (st->rho * rho_j);
#if CLSPH_VISCOSITY == 0
    {
        const float alpha = fluid_j ? sp->visc_alpha : sp->visc_alpha_wall;
        const floatV mu = sp->h * vd / (r2 + sp->eta2);
        coef += select((floatV)(0.0f), (-alpha * sp->c0) * mu / (0.5f * (st->rho + rho_j)), vd < 0.0f);
    }
#endif
    const floatV s = mf * coef;  // a_i += -m coef F (x_i - x_j) = m coef F rij
    st->ax += s * rx;
    st->ay += s * ry;
    st->az += s * rz;
#if CLSPH_VISCOSITY != 0
    const floatV lam = mf * sp->visc_laminar * r2 / ((st->rho + rho_j) * (r2 + sp->eta2));
    st->ax += lam * vx;
    st->ay += lam * vy;
    st->az += lam * vz;
#endif
#if CLSPH_VISCOSITY == 2
    {  // grad_i W = F (x_i - x_j) = -F rij; mf = m F
        const float4 a = tau[2u * j], b = tau[2u * j + 1u];
        const floatV xx = st->txx + a.x, xy = st->txy + a.y, xz = st->txz + a.z;
        const floatV yy = st->tyy + a.w, yz = st->tyz + b.x, zz = st->tzz + b.y;
        st->ax -= mf * (xx * rx + xy * ry + xz * rz);
        st->ay -= mf * (xy * rx + yy * ry + yz * rz);
        st->az -= mf * (xz * rx + yz * ry + zz * rz);
    }
#else
    (void)j;
#endif
}

#define LANES_T ForceLanes
#define LANES_INIT(st, base, count)                                              \
    do {                                                                         \
        float tvx[VW], tvy[VW], tvz[VW], trho[VW], tp[VW];                       \
        int tfluid[VW];                                                          \
        for (uint l = 0; l < VW; ++l) {                                          \
            const uint i_ = (base) + min(l, (count) - 1u);                       \
            const float4 vr = velrho[i_];                                        \
            tvx[l] = vr.x;                                                       \
            tvy[l] = vr.y;                                                       \
            tvz[l] = vr.z;                                                       \
            trho[l] = vr.w;                                                      \
            tp[l] = pressure_of(&sp, vr.w);                                      \
            tfluid[l] = (ids[i_] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID ? -1 : 0; \
        }                                                                        \
        (st).vx = vloadV(0, tvx);                                                \
        (st).vy = vloadV(0, tvy);                                                \
        (st).vz = vloadV(0, tvz);                                                \
        (st).rho = vloadV(0, trho);                                              \
        (st).p = vloadV(0, tp);                                                  \
        (st).fluid = vloadV(0, tfluid);                                          \
        (st).ax = (st).ay = (st).az = (st).drho = (floatV)(0.0f);                \
        LANES_INIT_SPS(st, base, count);                                         \
    } while (0)
#if CLSPH_VISCOSITY == 2
#define LANES_INIT_SPS(st, base, count)                                          \
    do {                                                                         \
        float t[6][VW];                                                          \
        for (uint l = 0; l < VW; ++l) {                                          \
            const uint i_ = (base) + min(l, (count) - 1u);                       \
            const float4 a = tau[2u * i_], b = tau[2u * i_ + 1u];                \
            t[0][l] = a.x;                                                       \
            t[1][l] = a.y;                                                       \
            t[2][l] = a.z;                                                       \
            t[3][l] = a.w;                                                       \
            t[4][l] = b.x;                                                       \
            t[5][l] = b.y;                                                       \
        }                                                                        \
        (st).txx = vloadV(0, t[0]);                                              \
        (st).txy = vloadV(0, t[1]);                                              \
        (st).txz = vloadV(0, t[2]);                                              \
        (st).tyy = vloadV(0, t[3]);                                              \
        (st).tyz = vloadV(0, t[4]);                                              \
        (st).tzz = vloadV(0, t[5]);                                              \
    } while (0)
#define LANES_PAIR(st, j, rx, ry, rz, r2, hit) \
    force_lanes(&(st), &sp, SEEN_VELRHO(j), ids[j], rx, ry, rz, r2, hit, tau, j)
#else
#define LANES_INIT_SPS(st, base, count) \
    do {                                \
    } while (0)
#define LANES_PAIR(st, j, rx, ry, rz, r2, hit) \
    force_lanes(&(st), &sp, SEEN_VELRHO(j), ids[j], rx, ry, rz, r2, hit, j)
#endif
#define LANES_STORE(st, base, count)                                                        \
    do {                                                                                    \
        float tax[VW], tay[VW], taz[VW], tdrho[VW];                                         \
        int tfluid[VW];                                                                     \
        vstoreV((st).ax, 0, tax);                                                           \
        vstoreV((st).ay, 0, tay);                                                           \
        vstoreV((st).az, 0, taz);                                                           \
        vstoreV((st).drho, 0, tdrho);                                                       \
        vstoreV((st).fluid, 0, tfluid);                                                     \
        for (uint l = 0; l < (count); ++l)                                                  \
            accel[(base) + l] = tfluid[l] ? (float4)(tax[l] + sp.gx, tay[l] + sp.gy, taz[l] + sp.gz, tdrho[l]) \
                                          : (float4)(0.0f, 0.0f, 0.0f, BOUNDARY_DRHO(tdrho[l])); \
    } while (0)
#endif

#include "neighbour_loop.h"
