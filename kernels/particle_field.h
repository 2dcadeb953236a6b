// The field an image is coloured by, of one fluid particle (render_field.cl, splat.cl): mode 1 its
// speed |v| (m/s), mode 2 its pressure (Pa) by the run's equation of state (sph_kernel.h
// pressure_of: Tait, B ((rho / rho0)^7 - 1)), from its velocity and density (velrho).
#ifndef CLSPH_PARTICLE_FIELD_H
#define CLSPH_PARTICLE_FIELD_H
#include "sph_kernel.h"

inline float particle_field(const uint mode, const SphParams* sp, const float4 vr) {
    return mode == 2u ? pressure_of(sp, vr.w) : length(vr.xyz);
}

#endif
