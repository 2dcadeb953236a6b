// The velocity a particle's neighbour j shows the interaction passes (forces.cl, sps.cl,
// floating.cl). Without -DCLSPH_NOSLIP it is velrho[j]: a boundary particle shows its wall's own
// velocity (0 at rest; a moving solid's or a floating body's, which kernels/motion.cl writes into
// velrho every step), and the kernels take no extra argument.
//
// -DCLSPH_NOSLIP (mDBC no-slip walls, boundaries.slip "no-slip"; English et al. 2021): a boundary
// particle shows 2 v_wall - v_G, the fluid's velocity at its ghost node G mirrored about the
// wall's, so that the velocity field the fluid's sums see crosses the wall smoothly and vanishes
// (relative to the wall) on the boundary interface. The mDBC pass (mdbc.cl) writes v_wall - v_G
// (0 without fluid at G) into the xyz of the boundary particle's entry of the force pass's output,
// which the kick makes `accel`: a boundary particle has no acceleration of its own (the kick, the
// drift and Symplectic's corrector read only w, its drho/dt, for it), and that array travels with
// the particle through reorders, migration, halo exchanges and checkpoints, so every device that
// holds the particle shows its owner's value, with no array added. The wall's velocity stays in
// velrho untouched: motion.cl writes it from the motion each step, the kick bounds the time step
// by it, and nothing ever takes the mirrored value for the wall's own. So what j shows is
//     velrho[j].xyz + wall_seen[j].xyz = v_wall(now) + v_wall(last pass) - v_G(last pass),
// for a wall at rest exactly -v_G; for a moving one the wall's own term is the present one.
#ifndef CLSPH_WALL_VELOCITY_H
#define CLSPH_WALL_VELOCITY_H
#include "shared.h"

#ifdef CLSPH_NOSLIP
#define NOSLIP_ARGS , __global const float4 *wall_seen
inline float4 seen_velrho(__global const float4* velrho, __global const uint* ids, __global const float4* wall_seen,
                          const uint j) {
    float4 v = velrho[j];
    if ((ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) v.xyz += wall_seen[j].xyz;
    return v;
}
#define SEEN_VELRHO(j) seen_velrho(velrho, ids, wall_seen, (j))
#else
#define NOSLIP_ARGS
#define SEEN_VELRHO(j) velrho[j]
#endif

#endif
