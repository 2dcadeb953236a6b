// Small kernels the runtime uses to check itself (and tests use to check the runtime).
#include "shared.h"

#ifdef CLSPH_SELFTEST_BROKEN
this line is deliberately not OpenCL C, to exercise build-error reporting
#endif

__kernel void axpy(const uint n, const float a, __global const float* x, __global float* y) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    y[i] = a * x[i] + y[i];
}

// Moves particles by v * dt in cell-offset space (the cell pass then settles them into cells):
// the drift of the integrator without any physics, for pipeline tests.
__kernel void drift(const uint n, const float dt, __global float4* pos, __global const float4* velrho) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float4 p = pos[i];
    p.xyz += velrho[i].xyz * dt;
    pos[i] = p;
}

// Busy work for timer tests: each item iterates a cheap recurrence `rounds` times.
__kernel void spin(const uint n, const uint rounds, __global float* out) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float x = (float)i * 1e-3f;
    for (uint r = 0; r < rounds; ++r) x = x * 0.999999f + 1e-6f;
    out[i] = x;
}
