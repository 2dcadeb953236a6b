// Leap-frog in kick-drift-kick form (the host keeps time in double), with the forces evaluated on
// predicted full-step velocity and density so that positions, velocities and densities the force
// pass sees belong to the same time level (a lagged density makes the acoustic modes unstable at
// CFL 0.2; this is the standard predictor for velocity-dependent SPH forces):
//   kick_drift:  x_{n+1} = x_n + (v_n + a_n dt/2) dt
//                v* = v_n + a_n dt,  rho* = rho_n + drho_n dt           (predicted, stored in velrho)
//   [cell pass (reorders accel too), forces at (x_{n+1}, v*, rho*) -> a_{n+1}, drho_{n+1}]
//   kick:        v_{n+1} = v* + (a_{n+1} - a_n) dt/2 = v_n + (a_n + a_{n+1}) dt/2
//                rho_{n+1} = rho* + (drho_{n+1} - drho_n) dt/2, then checks and the reductions for dt
// Boundary particles do not move here (those of moving solids are put by kernels/motion.cl after
// the drift); their density may not fall below rho0 (as DualSPHysics does for
// DBC), otherwise walls would suck fluid in.
#include "advance.h"

// dt is read from dt_f[0] (the device's clock writes it: step_clock.cl; the synchronous path writes
// it from the host).

__kernel void kick_drift(const uint first, const uint last, __global const float* dt_f, const float rho0,
                         const uint invalid_key, __global float4* pos, __global float4* velrho,
                         __global const float4* accel, __global const uint* ids, __global const uint* halt) {
    const float dt = dt_f[0];
    advance(first + (uint)get_global_id(0), last, dt, dt, 0.5f * dt, rho0, invalid_key, pos, velrho, accel, ids, halt);
}

// Second kick (old accelerations in `accel`, new ones in `accel_new`), then per work-group: max
// |v|^2 of fluid and boundary particles (a moving solid's: kernels/motion.cl), max |a|^2 of fluid, kinetic energy, fluid count into partials[group]; the lowest index
// of a particle with a non-finite value or a density outside [rho_min, rho_max] into *bad (the
// host, or step_clock.cl's end_step, sets it to 0xffffffff first). While *halt is set the step
// changes nothing: the old accelerations are copied over the new ones, so that swapping the two
// buffers after it leaves accel as it was.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void kick(
    const uint first, const uint last, __global const float* dt_f, const SphParams sp, const uint invalid_key,
    __global const float4* pos, __global float4* velrho, __global const float4* accel, __global float4* accel_new,
    __global const uint* ids, __global float4* partials, __global uint* bad, __global const uint* halt) {
    __local float4 red[WG];
    const uint lid = get_local_id(0);
    const bool halted = *halt != 0u;
    const float dt = dt_f[0];
    float4 acc = (float4)(0.0f);
    for (uint i = first + (uint)get_global_id(0); i < last; i += (uint)get_global_size(0)) {
        if (halted) {
            accel_new[i] = accel[i];
            continue;
        }
        if (as_uint(pos[i].w) == invalid_key) continue;
        float4 vr = velrho[i];
        const float4 a = accel_new[i];
        const float4 da = (a - accel[i]) * (0.5f * dt);
        const bool fluid = is_fluid(ids[i]);
        if (fluid) {
            vr += da;
        } else {
            vr.w = fmax(vr.w + da.w, sp.rho0);
        }
        velrho[i] = vr;
        const bool finite = isfinite(vr.x) && isfinite(vr.y) && isfinite(vr.z) && isfinite(vr.w) &&
                            isfinite(a.x) && isfinite(a.y) && isfinite(a.z) && isfinite(a.w);
        if (!finite || vr.w < sp.rho_min || vr.w > sp.rho_max) atomic_min(bad, i);
        if (fluid) {
            const float v2 = dot(vr.xyz, vr.xyz);
            acc.x = fmax(acc.x, v2);
            acc.y = fmax(acc.y, dot(a.xyz, a.xyz));
            acc.z += 0.5f * sp.mass * v2;
            acc.w += 1.0f;
        } else {
            acc.x = fmax(acc.x, dot(vr.xyz, vr.xyz));  // a moving wall's speed bounds the step too (0 at rest)
        }
    }
    red[lid] = acc;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint s = WG / 2; s > 0; s >>= 1) {
        if (lid < s) {
            const float4 o = red[lid + s];
            float4 m = red[lid];
            m.x = fmax(m.x, o.x);
            m.y = fmax(m.y, o.y);
            m.z += o.z;
            m.w += o.w;
            red[lid] = m;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid == 0) partials[get_group_id(0)] = red[0];
}

// Summation density: the new fluid densities computed by density.cl go into velrho.w.
__kernel void commit_density(const uint first, const uint last, __global const float* rho, __global float4* velrho) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last) return;
    velrho[i].w = rho[i];
}

// Symplectic (position Verlet predictor-corrector, as DualSPHysics offers), two force passes a step:
//   predict:  x_h = x_n + v_n dt/2,  v_h = v_n + a_n dt/2,  rho_h = rho_n + drho_n dt/2
//   [exchange, cell pass, forces at (x_h, v_h, rho_h) -> a_h, drho_h]
//   correct:  v_{n+1} = v_n + a_h dt,  x_{n+1} = x_h + v_{n+1} dt/2  (= x_n + (v_n + v_{n+1}) dt/2),
//             rho_{n+1} = rho_n (2 - eps) / (2 + eps),  eps = -(drho_h / rho_h) dt
//   [exchange, cell pass, forces at the new state -> a_{n+1}: the next predictor's, and the CFL step]
// v_n and rho_n are recovered from the half-step values and a_n (still in `accel`, reordered with
// the particles), so no copy of the old state is kept. Boundary particles do not move; their
// density follows the same rule, never below rho0 (with mDBC their drho is 0: unchanged here).
__kernel void symplectic_predict(const uint first, const uint last, __global const float* dt_f, const float rho0,
                                 const uint invalid_key, __global float4* pos, __global float4* velrho,
                                 __global const float4* accel, __global const uint* ids, __global const uint* halt) {
    const float hdt = 0.5f * dt_f[0];
    advance(first + (uint)get_global_id(0), last, hdt, hdt, 0.0f, rho0, invalid_key, pos, velrho, accel, ids, halt);
}

__kernel void symplectic_correct(const uint first, const uint last, __global const float* dt_f, const float rho0,
                                 const uint invalid_key, __global float4* pos, __global float4* velrho,
                                 __global const float4* accel, __global const float4* accel_half,
                                 __global const uint* ids, __global const uint* halt) {
    const uint i = first + (uint)get_global_id(0);
    if (i >= last || *halt != 0u) return;
    float4 p = pos[i];
    if (as_uint(p.w) == invalid_key) return;
    const float dt = dt_f[0], hdt = 0.5f * dt;
    float4 vr = velrho[i];
    const float4 a0 = accel[i], ah = accel_half[i];
    const float rho_n = vr.w - a0.w * hdt;
    const float eps = -(ah.w / vr.w) * dt;
    const float rho = rho_n * (2.0f - eps) / (2.0f + eps);
    if (is_fluid(ids[i])) {
        const float3 v = vr.xyz - a0.xyz * hdt + ah.xyz * dt;
        p.xyz += v * hdt;
        pos[i] = p;
        vr = (float4)(v, rho);
    } else {
        vr.w = fmax(rho, rho0);
    }
    velrho[i] = vr;
}
