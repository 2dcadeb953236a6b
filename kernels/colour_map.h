// The colour map of images coloured by a particle field (speed, pressure: clsph/render.hpp
// SurfaceColour): t in [0, 1] (the field's range) to RGB in [0, 1], piecewise linear through five
// stops, dark blue - blue - green - yellow - red (lightness rises to the yellow, so the slow or low
// end reads as dark). Read by both compilers: the kernels colour with it, the host draws the page's
// legend and the tests their expectations from it.
#ifndef CLSPH_COLOUR_MAP_H
#define CLSPH_COLOUR_MAP_H

#include "shared.h"

#define CLSPH_COLOUR_STOPS 5

inline void clsph_colour_map(float t, float* r, float* g, float* b) {
    const float R[CLSPH_COLOUR_STOPS] = {0.10f, 0.13f, 0.25f, 0.96f, 0.86f};
    const float G[CLSPH_COLOUR_STOPS] = {0.12f, 0.45f, 0.74f, 0.84f, 0.18f};
    const float B[CLSPH_COLOUR_STOPS] = {0.45f, 0.88f, 0.42f, 0.20f, 0.14f};
    if (!(t > 0.0f)) t = 0.0f;  // NaN too
    if (t > 1.0f) t = 1.0f;
    const float x = t * (float)(CLSPH_COLOUR_STOPS - 1);
    int k = (int)x;
    if (k > CLSPH_COLOUR_STOPS - 2) k = CLSPH_COLOUR_STOPS - 2;
    const float f = x - (float)k;
    *r = R[k] + (R[k + 1] - R[k]) * f;
    *g = G[k] + (G[k + 1] - G[k]) * f;
    *b = B[k] + (B[k + 1] - B[k]) * f;
}

// A float's bits as a uint that orders as the float does (negative ones too): the field's bounds
// are kept with atomic_min / atomic_max on these.
inline clsph_uint clsph_ordered_bits(clsph_uint bits) {
    return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}
inline clsph_uint clsph_unordered_bits(clsph_uint u) {
    return (u & 0x80000000u) ? (u & 0x7fffffffu) : ~u;
}

#endif
