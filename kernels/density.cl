// Summation density (the paper's first pass): rho_i = sum_j m W_ij over all neighbours, self
// included, for fluid particles; boundary particles keep integrating the continuity equation (DBC).
// Free-surface treatment: a particle whose kernel is incomplete (theta_i = sum_j m / rho_j W_ij
// below 0.95: neighbours missing above the surface) may not fall below rho0, so the surface does
// not pull itself together with negative pressures. Writes the new density to `rho_out`.
#include "sph_kernel.h"

typedef struct {
    float4 pos;
    float rho;
} DensityNeighbour;

typedef struct {
    float mw, vw;
    uint fluid;
    float rho;
} DensityState;

#define INTERACTION_NAME summation_density
#define INTERACTION_ARGS \
    , const SphParams sp, __global const float4 *velrho, __global const uint *ids, __global float *rho_out
#define NEIGHBOUR_T DensityNeighbour
#define LOAD_NEIGHBOUR(nb, j)       \
    do {                            \
        (nb).rho = velrho[j].w;     \
    } while (0)
#define STATE_T DensityState
#define STATE_INIT(st, i, self)                                              \
    do {                                                                     \
        (st).mw = 0.0f;                                                      \
        (st).vw = 0.0f;                                                      \
        (st).rho = (self).rho;                                               \
        (st).fluid = (ids[i] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;       \
    } while (0)
#define PAIR(st, self, nb, i, j, rij, r2)                     \
    do {                                                      \
        const float w = kernel_w(&sp, sqrt(r2));              \
        (st).mw += sp.mass * w;                               \
        (st).vw += sp.mass / (nb).rho * w;                    \
    } while (0)
#define STATE_STORE(st, i) \
    rho_out[i] = !(st).fluid ? (st).rho : ((st).vw < 0.95f ? fmax((st).mw, sp.rho0) : (st).mw)

#ifdef CLSPH_LANES
// The CPU form (neighbour_loop.h, lanes): the same sums for CLSPH_LANES particles of one cell.
#include "lanes.h"

typedef struct {
    floatV mw, vw, rho;
    intV fluid;
} DensityLanes;

#define LANES_T DensityLanes
#define LANES_INIT(st, base, count)                                              \
    do {                                                                         \
        float trho[VW];                                                          \
        int tfluid[VW];                                                          \
        for (uint l = 0; l < VW; ++l) {                                          \
            const uint i_ = (base) + min(l, (count) - 1u);                       \
            trho[l] = velrho[i_].w;                                              \
            tfluid[l] = (ids[i_] >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID ? -1 : 0; \
        }                                                                        \
        (st).rho = vloadV(0, trho);                                              \
        (st).fluid = vloadV(0, tfluid);                                          \
        (st).mw = (st).vw = (floatV)(0.0f);                                      \
    } while (0)
#define LANES_PAIR(st, j, rx, ry, rz, r2, hit)                                             \
    do {                                                                                   \
        const floatV w = select((floatV)(0.0f), kernel_w_lanes(&sp, sqrt(r2)), hit);       \
        (st).mw += sp.mass * w;                                                            \
        (st).vw += (sp.mass / velrho[j].w) * w;                                            \
    } while (0)
#define LANES_STORE(st, base, count)                                                       \
    do {                                                                                   \
        float tmw[VW], tvw[VW], trho[VW];                                                  \
        int tfluid[VW];                                                                    \
        vstoreV((st).mw, 0, tmw);                                                          \
        vstoreV((st).vw, 0, tvw);                                                          \
        vstoreV((st).rho, 0, trho);                                                        \
        vstoreV((st).fluid, 0, tfluid);                                                    \
        for (uint l = 0; l < (count); ++l)                                                 \
            rho_out[(base) + l] = !tfluid[l] ? trho[l] : (tvw[l] < 0.95f ? fmax(tmw[l], sp.rho0) : tmw[l]); \
    } while (0)
#endif

#include "neighbour_loop.h"
