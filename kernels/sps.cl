// The sub-particle-scale stress of physics.viscosity "laminar+sps" (Dalrymple & Rogers 2006, as
// DualSPHysics computes it), a pass before the force pass of the same step (forces.cl uses it with
// -DCLSPH_VISCOSITY=2). Per fluid particle i, the velocity gradient
//     G_ab = sum_j (m / rho_j) (v_j - v_i)_a dW_ij/dx_b,  off-diagonal entries summed: G_ab + G_ba,
// over fluid and boundary neighbours alike (a boundary neighbour's velocity as wall_velocity.h has
// it: with no-slip walls the mirrored one); then, with |S|^2 = 2 (G_xx^2 + G_yy^2 + G_zz^2) +
// G_xy^2 + G_xz^2 + G_yz^2, the Smagorinsky eddy viscosity nu_t = (Cs dp)^2 |S| (Cs = 0.12) and the
// stress over rho_i^2 (what the force pass sums),
//     tau_aa / rho_i^2 = (2 nu_t G_aa - (2/3) nu_t div v - (2/3) CI dp^2 |S|^2) / rho_i  (CI = 0.0066)
//     tau_ab / rho_i^2 = nu_t (G_ab + G_ba) / rho_i.
// tau[2 i] = (xx, xy, xz, yy), tau[2 i + 1] = (yz, zz, 0, 0); boundary particles get 0.
// Launched over every particle the device holds, ghosts included: a ghost one column from the
// device's own has all its neighbours here (the exchange sends two halo columns with SPS), so its
// stress is bitwise its owner's; those of the outer ghost column miss neighbours, and no owned
// particle reaches them.
#include "sph_kernel.h"
#include "wall_velocity.h"

typedef struct {
    float4 pos;
    float4 velrho;
    uint fluid;
} SpsNeighbour;

typedef struct {
    float xx, xy, xz, yy, yz, zz;
    float rho;
    uint fluid;
} SpsGradient;

inline void sps_pair(SpsGradient* st, const SphParams* sp, const SpsNeighbour* self, const SpsNeighbour* nb,
                     const float3 rij, const float r2) {
    if (!st->fluid || r2 <= 1e-18f) return;
    const float f = kernel_f(sp, sqrt(r2));
    const float3 fr = f * (-rij);  // grad_i W_ij
    const float3 dv = self->velrho.xyz - nb->velrho.xyz;
    const float vol = -sp->mass / nb->velrho.w;  // (v_j - v_i) m / rho_j = vol (v_i - v_j)
    const float3 a = (vol * dv.x) * fr, b = (vol * dv.y) * fr, c = (vol * dv.z) * fr;
    st->xx += a.x;
    st->xy += a.y + b.x;
    st->xz += a.z + c.x;
    st->yy += b.y;
    st->yz += b.z + c.y;
    st->zz += c.z;
}

#define INTERACTION_NAME sps_stress
#define INTERACTION_ARGS \
    , const SphParams sp, __global const float4 *velrho, __global const uint *ids, __global float4 *tau NOSLIP_ARGS
#define NEIGHBOUR_T SpsNeighbour
#define LOAD_NEIGHBOUR(nb, j)                                          \
    do {                                                               \
        (nb).velrho = SEEN_VELRHO(j);                                  \
        (nb).fluid = (ids[j] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID; \
    } while (0)
#define STATE_T SpsGradient
#define STATE_INIT(st, i, self)                                                        \
    do {                                                                               \
        (st).xx = (st).xy = (st).xz = (st).yy = (st).yz = (st).zz = 0.0f;              \
        (st).rho = (self).velrho.w;                                                    \
        (st).fluid = (self).fluid;                                                     \
    } while (0)
#define PAIR(st, self, nb, i, j, rij, r2) sps_pair(&(st), &sp, &(self), &(nb), (rij), (r2))

inline void sps_store(const SpsGradient* g, const SphParams* sp, __global float4* tau, const uint i) {
    float4 t0 = (float4)(0.0f), t1 = (float4)(0.0f);
    if (g->fluid) {
        const float diag = g->xx * g->xx + g->yy * g->yy + g->zz * g->zz;
        const float s2 = diag + diag + g->xy * g->xy + g->xz * g->xz + g->yz * g->yz;
        const float nu_t = sp->sps_smag * sqrt(s2);
        const float iso = -((2.0f / 3.0f) * nu_t * (g->xx + g->yy + g->zz) + sp->sps_blin * s2);
        const float two = nu_t + nu_t, inv_rho = 1.0f / g->rho;
        t0 = (float4)(two * g->xx + iso, nu_t * g->xy, nu_t * g->xz, two * g->yy + iso) * inv_rho;
        t1 = (float4)(nu_t * g->yz, two * g->zz + iso, 0.0f, 0.0f) * inv_rho;
    }
    tau[2u * i] = t0;
    tau[2u * i + 1u] = t1;
}
#define STATE_STORE(st, i) sps_store(&(st), &sp, tau, (i))

#include "neighbour_loop.h"
