// One particle's first half of a step (Leap-frog's kick_drift, Symplectic's predictor:
// kernels/integrate.cl), shared with the step ahead's fused first launch (kernels/cells.cl,
// drift_settle_keys), so that both run the same arithmetic.
#ifndef CLSPH_ADVANCE_H
#define CLSPH_ADVANCE_H
#include "shared.h"

inline bool is_fluid(const uint id) { return (id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID; }

// x += (v + a lead) drift, v += a kick, rho += drho kick (a boundary particle: only its density,
// never below rho0). Past `last`, while halted, or outside the domain: nothing. While *halt is set
// (step_clock.cl) a step changes nothing. A particle with the invalid key left the domain and
// waits at the end of the sorted arrays to be dropped: it rests.
inline void advance(const uint i, const uint last, const float kick, const float drift, const float lead,
                    const float rho0, const uint invalid_key, __global float4* pos, __global float4* velrho,
                    __global const float4* accel, __global const uint* ids, __global const uint* halt) {
    if (i >= last || *halt != 0u) return;
    float4 p = pos[i];
    if (as_uint(p.w) == invalid_key) return;
    float4 vr = velrho[i];
    const float4 a = accel[i];
    if (is_fluid(ids[i])) {
        p.xyz += (vr.xyz + a.xyz * lead) * drift;
        pos[i] = p;
        vr.xyz += a.xyz * kick;
        vr.w += a.w * kick;
    } else {
        vr.w = fmax(vr.w + a.w * kick, rho0);
    }
    velrho[i] = vr;
}

#endif
