// Smoothing kernels, 3-D, support 2h. Selected with -DCLSPH_KERNEL_CUBIC (default Wendland C2).
//   Wendland C2 (Wendland 1995): W = aD (1 - q/2)^4 (2q + 1),  aD = 21 / (16 pi h^3)
//   cubic spline (Monaghan & Lattanzio 1985): aD = 1 / (pi h^3),
//       W = aD (1 - 1.5 q^2 + 0.75 q^3) for q < 1,  aD 0.25 (2 - q)^3 for 1 <= q < 2
// kernel_f(r) returns F with grad_i W_ij = F * (x_i - x_j), i.e. F = (dW/dr) / r (F <= 0).
#ifndef CLSPH_SPH_KERNEL_H
#define CLSPH_SPH_KERNEL_H
#include "shared.h"

inline float kernel_w(const SphParams* sp, const float r) {
    const float q = r * sp->inv_h;
#ifdef CLSPH_KERNEL_CUBIC
    if (q >= 2.0f) return 0.0f;
    if (q < 1.0f) return sp->kernel_norm * (1.0f - 1.5f * q * q + 0.75f * q * q * q);
    const float t = 2.0f - q;
    return sp->kernel_norm * 0.25f * t * t * t;
#else
    if (q >= 2.0f) return 0.0f;
    const float t = 1.0f - 0.5f * q;
    const float t2 = t * t;
    return sp->kernel_norm * t2 * t2 * (2.0f * q + 1.0f);
#endif
}

inline float kernel_f(const SphParams* sp, const float r) {
    const float q = r * sp->inv_h;
#ifdef CLSPH_KERNEL_CUBIC
    if (q >= 2.0f || r <= 0.0f) return 0.0f;
    const float dwdq = q < 1.0f ? (-3.0f * q + 2.25f * q * q) : (-0.75f * (2.0f - q) * (2.0f - q));
    return sp->kernel_norm * sp->inv_h * dwdq / r;
#else
    // dW/dr = aD/h * (-5 q) (1 - q/2)^3, and q / r = 1/h, so F needs no division by r.
    if (q >= 2.0f) return 0.0f;
    const float t = 1.0f - 0.5f * q;
    return -5.0f * sp->kernel_norm * sp->inv_h * sp->inv_h * t * t * t;
#endif
}

// Tait equation of state with gamma = 7.
inline float pressure_of(const SphParams* sp, const float rho) {
    const float x = rho * sp->inv_rho0;
    const float x2 = x * x;
    const float x3 = x2 * x;
    return sp->eos_b * (x3 * x3 * x - 1.0f);
}

#endif
