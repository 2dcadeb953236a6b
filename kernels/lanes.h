// The CPU form's vector lanes (-DCLSPH_LANES=8 or 16): the particles of one cell side by side in
// OpenCL vector types, so that a CPU compiler (pocl, llvmpipe) runs each candidate's test and pair
// terms once for 8 or 16 particles in SIMD registers instead of once per particle.
#ifndef CLSPH_LANES_H
#define CLSPH_LANES_H
#include "sph_kernel.h"

#define CLSPH_CAT_(a, b) a##b
#define CLSPH_CAT(a, b) CLSPH_CAT_(a, b)
#define VW CLSPH_LANES
#define floatV CLSPH_CAT(float, CLSPH_LANES)
#define intV CLSPH_CAT(int, CLSPH_LANES)
#define vloadV CLSPH_CAT(vload, CLSPH_LANES)
#define vstoreV CLSPH_CAT(vstore, CLSPH_LANES)
#define convert_floatV CLSPH_CAT(convert_float, CLSPH_LANES)

// kernel_w / kernel_f of sph_kernel.h for lanes inside the support (q < 2); lanes outside are
// masked by the caller.
inline floatV kernel_w_lanes(const SphParams* sp, const floatV r) {
    const floatV q = r * sp->inv_h;
#ifdef CLSPH_KERNEL_CUBIC
    const floatV t = 2.0f - q;
    const floatV inner = 1.0f - 1.5f * q * q + 0.75f * q * q * q;
    return sp->kernel_norm * select(0.25f * t * t * t, inner, q < 1.0f);
#else
    const floatV t = 1.0f - 0.5f * q;
    const floatV t2 = t * t;
    return sp->kernel_norm * t2 * t2 * (2.0f * q + 1.0f);
#endif
}

inline floatV kernel_f_lanes(const SphParams* sp, const floatV r) {
    const floatV q = r * sp->inv_h;
#ifdef CLSPH_KERNEL_CUBIC
    const floatV dwdq = select(-0.75f * (2.0f - q) * (2.0f - q), -3.0f * q + 2.25f * q * q, q < 1.0f);
    return sp->kernel_norm * sp->inv_h * dwdq / r;
#else
    const floatV t = 1.0f - 0.5f * q;
    return -5.0f * sp->kernel_norm * sp->inv_h * sp->inv_h * t * t * t;
#endif
}

#endif
