// The nearest depth so far, for the rasterisers (render.cl, splat.cl): depths are positive floats,
// whose bits order as the values do, kept with a 32-bit atomic_min, or (-DCLSPH_DEPTH_BY_CAS, where
// the quirks layer says the driver's atomic_min loses writes) a compare-and-swap loop.
#ifndef CLSPH_DEPTH_MIN_H
#define CLSPH_DEPTH_MIN_H

inline void depth_min(volatile __global uint* p, const uint v) {
#ifdef CLSPH_DEPTH_BY_CAS
    uint old = *p;
    while (v < old) {
        const uint prev = atomic_cmpxchg(p, old, v);
        if (prev == old) break;
        old = prev;
    }
#else
    atomic_min(p, v);
#endif
}

#endif
