// Images coloured by a particle field (host/src/render/field.cpp): the field of a fluid particle
// (mode 1: speed |v|, m/s; mode 2: pressure by the equation of state the run uses, Pa), its bounds
// over the particles a device owns, and its Shepard average at the vertices of the free surface.
//   field_bounds   per owned particle: atomic min and max of the field (fluid only), as ordered bits
//   vertex_field   per vertex (float4, world coordinates): sum_j f_j V_j W / sum_j V_j W over the
//                  fluid particles within the support (owned and ghosts), mapped onto [0, 1] by
//                  `range` (lo, hi); -1 where no fluid particle is within the support
#include "grid.h"
#include "sph_kernel.h"
#include "colour_map.h"
#include "particle_field.h"

inline void bound_min(volatile __global uint* p, const uint v) {
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

inline void bound_max(volatile __global uint* p, const uint v) {
#ifdef CLSPH_DEPTH_BY_CAS
    uint old = *p;
    while (v > old) {
        const uint prev = atomic_cmpxchg(p, old, v);
        if (prev == old) break;
        old = prev;
    }
#else
    atomic_max(p, v);
#endif
}

// bounds[0] the least field (ordered bits), bounds[1] the greatest; the host fills them with
// (all ones, 0) first.
__kernel void field_bounds(const uint first, const uint count, const uint mode, const SphParams sp,
                           __global const float4* velrho, __global const uint* ids, __global uint* bounds) {
    const SphParams s = sp;  // every argument read before any branch (kernels/render.cl)
    const uint begin = first, n = count, m = mode;
    __global const float4* const p_vr = velrho;
    __global const uint* const p_ids = ids;
    __global uint* const p_bounds = bounds;
    const uint i = get_global_id(0);
    if (i >= n) return;
    if ((p_ids[begin + i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const float f = particle_field(m, &s, p_vr[begin + i]);
    if (!isfinite(f)) return;
    const uint o = clsph_ordered_bits(as_uint(f));
    bound_min(&p_bounds[0], o);
    bound_max(&p_bounds[1], o);
}

// One axis of a point's cell and offset (as surface.cl's locate_axis): false outside the domain.
inline bool field_locate(const float x, const float cell, const uint n, const uint periodic, uint* c, float* off) {
    float rel = x;
    if (periodic) {
        const float len = cell * (float)n;
        rel -= floor(rel / len) * len;
    }
    float ci = floor(rel / cell);
    if (periodic && ci >= (float)n) ci = (float)(n - 1u);
    if (!(ci >= 0.0f) || ci >= (float)n) return false;
    *c = (uint)ci;
    *off = rel - (ci + 0.5f) * cell;
    return true;
}

__kernel void vertex_field(const uint vertices, const uint cells, const GridParams g, const SphParams sp,
                           const uint mode, const float4 lo, const float2 range, __global const float4* points,
                           __global const uint* cell_key, __global const uint* cell_start,
                           __global const float4* pos, __global const float4* velrho, __global const uint* ids,
                           __global float* out) {
    const GridParams gp = g;  // every argument read before any branch (kernels/render.cl)
    const SphParams s = sp;
    const uint n = vertices, ncells = cells, m = mode;
    const float3 origin = lo.xyz;
    const float r_lo = range.x, r_hi = range.y;
    __global const float4* const p_points = points;
    __global const uint* const p_key = cell_key;
    __global const uint* const p_start = cell_start;
    __global const float4* const p_pos = pos;
    __global const float4* const p_vr = velrho;
    __global const uint* const p_ids = ids;
    __global float* const p_out = out;
    const uint v = get_global_id(0);
    if (v >= n) return;
    const float3 x = p_points[v].xyz - origin;
    uint cs, ca, cb;
    float os, oa, ob;
    float weight = 0.0f, sum = 0.0f;
    if (field_locate(S_OF(x), gp.cell_s, gp.n_s, 0u, &cs, &os) &&
        field_locate(A_OF(x), gp.cell_a, gp.n_a, gp.periodic_a, &ca, &oa) &&
        field_locate(B_OF(x), gp.cell_b, gp.n_b, 0u, &cb, &ob)) {
        const uint key = make_key(gp, cs, ca, cb);
        float4 q = (float4)(0.0f);
        S_OF(q) = os;
        A_OF(q) = oa;
        B_OF(q) = ob;
        q.w = as_float(key);
        for (uint r = 0; r < ROWS; ++r) {
            uint begin, end;
            if (!row_of_point(gp, ncells, p_key, p_start, (int)cs, (int)ca, cb, r, &begin, &end)) continue;
            for (uint j = begin; j < end; ++j) {
                if ((p_ids[j] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) continue;
                const float4 pj = p_pos[j];
                const float3 d = relative_position(gp, key, q, pos_key(pj), pj);
                const float r2 = dot(d, d);
                if (r2 >= s.support2) continue;
                const float4 vr = p_vr[j];
                const float vw = s.mass / vr.w * kernel_w(&s, sqrt(r2));
                weight += vw;
                sum += vw * particle_field(m, &s, vr);
            }
        }
    }
    float t = -1.0f;
    if (weight > 0.0f) {
        const float f = sum / weight;
        t = r_hi > r_lo ? clamp((f - r_lo) / (r_hi - r_lo), 0.0f, 1.0f) : 0.0f;
    }
    p_out[v] = t;
}
