// Floating bodies (host/src/multi/rigid_bodies.hpp): the fluid's force on each particle of a
// floating body, and per body the sums of the force and of the moments r0 F, in 64-bit fixed point.
//   floating_forces: per owned particle of a floating body (body_rest[id].w >= 0) the force of
//     its fluid neighbours, the reaction of the pair terms the fluid gets from it in forces.cl:
//       F_i = -m^2 sum_j [(p_i + p_j) / (rho_i rho_j) + Pi_ij] F_ij (x_i - x_j)
//     (v_i the velocity the fluid saw at i, wall_velocity.h: with no-slip walls the mirrored one)
//     (pressure; Monaghan's viscosity with alpha_wall, where v_ij . x_ij < 0, or with
//     -DCLSPH_VISCOSITY=1 the laminar term's reaction, m^2 4 nu F r^2 / ((rho_i + rho_j)(r^2 +
//     eta^2)) v_ij); others get 0.
//   floating_sums: per body and work-group, over the owned particles of the body, the 12 sums
//     F (3) and M_ab = r0_a F_b (9, row-major; r0 = body_rest[id].xyz, the particle's offset from
//     the body's centre at rest), each term rounded to 2^-32 first (convert_long_sat_rte), so that
//     integer sums in any order and over any split of the particles give the same bits. The host
//     adds the partials of every group and device (RigidBodies::set_forces turns M into torque).
#include "sph_kernel.h"
#include "wall_velocity.h"

#ifndef CLSPH_VISCOSITY
#define CLSPH_VISCOSITY 0
#endif

inline int body_of(const uint word, __global const float4* body_rest, const uint body_ids) {
    if ((word >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID) return -1;
    const uint id = word & CLSPH_ID_MASK;
    return id < body_ids ? (int)body_rest[id].w : -1;
}

typedef struct {
    float4 pos;
    float4 velrho;
    uint fluid;
} BodyNeighbour;

typedef struct {
    float3 acc;
    float p, rho;
} BodyForce;

inline void body_pair(BodyForce* st, const SphParams* sp, const BodyNeighbour* self, const BodyNeighbour* nb,
                      const float3 rij, const float r2) {
    if (!nb->fluid || r2 <= 1e-18f) return;
    const float r = sqrt(r2);
    const float f = kernel_f(sp, r);
    const float3 d = -rij;  // x_i - x_j
    const float3 vij = self->velrho.xyz - nb->velrho.xyz;
    const float rho_j = nb->velrho.w;
    const float p_j = pressure_of(sp, rho_j);
    float coef = (st->p + p_j) / (st->rho * rho_j);
#if CLSPH_VISCOSITY == 0
    const float vd = dot(vij, d);
    if (vd < 0.0f) {
        const float mu = sp->h * vd / (r2 + sp->eta2);
        coef += -sp->visc_alpha_wall * sp->c0 * mu / (0.5f * (st->rho + rho_j));
    }
    st->acc += (-sp->mass * coef * f) * d;
#else
    st->acc += (-sp->mass * coef * f) * d;
    st->acc += (sp->mass * sp->visc_laminar * f * r2 / ((st->rho + rho_j) * (r2 + sp->eta2))) * vij;
#endif
}

#define INTERACTION_NAME floating_forces
#define INTERACTION_ARGS                                                                                \
    , const SphParams sp, __global const float4 *velrho, __global const uint *ids,                      \
        __global const float4 *body_rest, const uint body_ids, __global float4 *force NOSLIP_ARGS
#define NEIGHBOUR_T BodyNeighbour
#define LOAD_NEIGHBOUR(nb, j)                                          \
    do {                                                               \
        (nb).velrho = SEEN_VELRHO(j);                                  \
        (nb).fluid = (ids[j] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID; \
    } while (0)
#define STATE_T BodyForce
#define STATE_INIT(st, i, self)                  \
    do {                                         \
        (st).acc = (float3)(0.0f);               \
        (st).rho = (self).velrho.w;              \
        (st).p = pressure_of(&sp, (st).rho);     \
    } while (0)
#define PAIR(st, self, nb, i, j, rij, r2) body_pair(&(st), &sp, &(self), &(nb), (rij), (r2))
#define SKIP_PARTICLE(self) (body_of(ids[i], body_rest, body_ids) < 0)
#define STORE_SKIPPED(i) force[i] = (float4)(0.0f)
#define STATE_STORE(st, i) force[i] = (float4)(sp.mass * (st).acc, 0.0f)

#include "neighbour_loop.h"

#define FIX(v) convert_long_sat_rte((v) * 4294967296.0f)

// Launched with bodies * groups work-groups of WG: group k sums body k / groups over the particles
// first + (k % groups) WG + lid, strided by groups WG. partials[(body groups + group) 12 + s].
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void floating_sums(
    const uint first, const uint last, const uint groups, __global const float4* force, __global const uint* ids,
    __global const float4* body_rest, const uint body_ids, __global long* partials) {
    __local long red[WG];
    const uint lid = get_local_id(0);
    const uint body = (uint)get_group_id(0) / groups, group = (uint)get_group_id(0) % groups;
    long s[12];
    for (uint k = 0; k < 12u; ++k) s[k] = 0;
    for (uint i = first + group * WG + lid; i < last; i += groups * WG) {
        if (body_of(ids[i], body_rest, body_ids) != (int)body) continue;
        const float3 f = force[i].xyz;
        const float3 r0 = body_rest[ids[i] & CLSPH_ID_MASK].xyz;
        s[0] += FIX(f.x);
        s[1] += FIX(f.y);
        s[2] += FIX(f.z);
        s[3] += FIX(r0.x * f.x);
        s[4] += FIX(r0.x * f.y);
        s[5] += FIX(r0.x * f.z);
        s[6] += FIX(r0.y * f.x);
        s[7] += FIX(r0.y * f.y);
        s[8] += FIX(r0.y * f.z);
        s[9] += FIX(r0.z * f.x);
        s[10] += FIX(r0.z * f.y);
        s[11] += FIX(r0.z * f.z);
    }
    for (uint k = 0; k < 12u; ++k) {
        red[lid] = s[k];
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint h = WG / 2; h > 0; h >>= 1) {
            if (lid < h) red[lid] += red[lid + h];
            barrier(CLK_LOCAL_MEM_FENCE);
        }
        if (lid == 0) partials[((ulong)body * groups + group) * 12u + k] = red[0];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}
