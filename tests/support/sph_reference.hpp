// The smoothing kernels in plain double-precision C++: the reference the device kernels
// (kernels/sph_kernel.h) are tested against.
#pragma once
#include "clsph/scene.hpp"

namespace clsph::test {

inline double reference_w(KernelType k, double h, double r) {
    const double pi = 3.14159265358979323846, q = r / h;
    if (q >= 2) return 0;
    if (k == KernelType::wendland_c2) {
        const double t = 1 - q / 2;
        return 21.0 / (16 * pi * h * h * h) * t * t * t * t * (2 * q + 1);
    }
    const double a = 1 / (pi * h * h * h);
    return q < 1 ? a * (1 - 1.5 * q * q + 0.75 * q * q * q) : a * 0.25 * (2 - q) * (2 - q) * (2 - q);
}

// (dW/dr) / r, so that grad_i W_ij = reference_f * (x_i - x_j).
inline double reference_f(KernelType k, double h, double r) {
    const double pi = 3.14159265358979323846, q = r / h;
    if (q >= 2 || r <= 0) return 0;
    if (k == KernelType::wendland_c2) {
        const double t = 1 - q / 2;
        return -5 * 21.0 / (16 * pi * h * h * h) / (h * h) * t * t * t;
    }
    const double a = 1 / (pi * h * h * h);
    return a / h * (q < 1 ? (-3 * q + 2.25 * q * q) : (-0.75 * (2 - q) * (2 - q))) / r;
}

}  // namespace clsph::test
