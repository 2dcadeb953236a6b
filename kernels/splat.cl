// Screen-space fluid rendering, the splat pass (host/src/render/splat.cpp): each fluid particle a
// device owns is a sphere of radius `radius`, intersected exactly with the ray of every pixel its
// bounding square covers. A pixel keeps the nearest hit's depth (distance along the camera's
// forward axis, as kernels/render.cl keeps it) with a 32-bit atomic_min on the float's bits, and
// sums the chord lengths through every sphere it sees (the fluid's thickness) in fixed point with
// atomic_add: integer sums do not depend on the order of the additions, so the thickness is the
// same whichever device draws which particle and the images of several devices add up exactly.
#include "grid.h"
#include "depth_min.h"
#include "particle_field.h"

// Particles [first, first + count) of the store. `lo` is the domain's min corner minus the eye
// (the host subtracts in double, so positions near a far-away eye keep their resolution), view is
// (pixels per unit of x / z, image centre x, y, sphere radius), unit the metres of one thickness
// count. Boundary particles and particles waiting to leave (invalid key) are not drawn. With a
// field (mode 1 speed, 2 pressure: particle_field.h), field_sum sums t * chord in the same counts
// as the thickness, t the particle's field mapped onto [0, 1] by range (lo, hi): the field's mean
// along the pixel's ray through the water, weighted by chord length, is field_sum / thickness (and
// as exact and independent of the order and of the devices as the thickness).
__kernel void splat_particles(const uint first, const uint count, const GridParams g, const float4 lo,
                              const float4 right, const float4 up, const float4 forward, const float4 view,
                              const uint2 size, const float unit, const uint mode, const float2 range,
                              const SphParams sp, __global const float4* pos, __global const uint* ids,
                              __global const float4* velrho, __global uint* depth, __global uint* thickness,
                              __global uint* field_sum) {
    // Every argument read before any branch (Mesa rusticl 22.3: see kernels/render.cl).
    const GridParams gp = g;
    const float3 origin = lo.xyz, ax = right.xyz, ay = up.xyz, az = forward.xyz;
    const float scale = view.x, cx = view.y, cy = view.z, r = view.w;
    const int w = (int)size.x, h = (int)size.y;
    const float inv_unit = 1.0f / unit;
    __global const float4* const p_pos = pos;
    __global const uint* const p_ids = ids;
    __global uint* const p_depth = depth;
    __global uint* const p_thick = thickness;
    __global const float4* const p_vr = velrho;
    __global uint* const p_field = field_sum;
    const uint field_mode = mode;
    const float f_lo = range.x, f_hi = range.y;
    const SphParams s = sp;
    const uint begin = first, n = count;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float4 p = p_pos[begin + i];
    if ((p_ids[begin + i] >> CLSPH_TYPE_SHIFT) != CLSPH_TYPE_FLUID) return;
    const uint key = pos_key(p);
    if (key == gp.invalid_key) return;
    float3 cell;
    COMP(cell, AXIS_S) = ((float)key_s(gp, key) + 0.5f) * gp.cell_s;
    COMP(cell, AXIS_A) = ((float)key_a(gp, key) + 0.5f) * gp.cell_a;
    COMP(cell, AXIS_B) = ((float)key_b(gp, key) + 0.5f) * gp.cell_b;
    const float3 x = origin + cell + p.xyz;  // the centre, relative to the eye
    const float3 c = (float3)(dot(x, ax), dot(x, ay), dot(x, az));  // camera axes: right, up, forward
    if (c.z <= 1.01f * r) return;  // behind the eye or around it
    // The sphere's silhouette lies within scale * r / sqrt(z^2 - r^2) of the projected centre
    // (exactly, on the axis; off axis the projection stretches, by 1 / cos^2 of the angle at most).
    const float px = cx + scale * c.x / c.z, py = cy - scale * c.y / c.z;
    const float k = scale * r / sqrt(c.z * c.z - r * r);
    const float stretch = 1.0f + (c.x * c.x + c.y * c.y) / (c.z * c.z);
    const float reach = k * stretch + 1.0f;
    const int x0 = max(0, (int)floor(px - reach)), x1 = min(w - 1, (int)ceil(px + reach));
    const int y0 = max(0, (int)floor(py - reach)), y1 = min(h - 1, (int)ceil(py + reach));
    if (x1 < x0 || y1 < y0 || (x1 - x0 + 1) * (y1 - y0 + 1) > 1 << 18) return;  // off screen, or at the lens
    const float r2 = r * r;
    float t = 0.0f;
    if (field_mode != 0u) {
        const float f = particle_field(field_mode, &s, p_vr[begin + i]);
        t = f_hi > f_lo ? clamp((f - f_lo) / (f_hi - f_lo), 0.0f, 1.0f) : 0.0f;
        if (!isfinite(t)) t = 0.0f;
    }
    for (int y = y0; y <= y1; ++y)
        for (int xx = x0; xx <= x1; ++xx) {
            // The pixel's ray (u, v, 1), unit direction d; the centre's distance from it through
            // the perpendicular vector itself (no difference of two large squares).
            const float3 ray = (float3)(((float)xx + 0.5f - cx) / scale, (cy - (float)y - 0.5f) / scale, 1.0f);
            const float3 d = normalize(ray);
            const float along = dot(c, d);
            const float3 perp = c - along * d;
            const float miss2 = dot(perp, perp);
            if (miss2 >= r2) continue;
            const float half_chord = sqrt(r2 - miss2);
            const float z = (along - half_chord) * d.z;  // the front hit's depth along forward
            const uint at = (uint)y * (uint)w + (uint)xx;
            depth_min(&p_depth[at], as_uint(z));
            const uint chord = max(1u, (uint)(2.0f * half_chord * inv_unit + 0.5f));  // drawn: at least 1
            atomic_add(&p_thick[at], chord);
            if (field_mode != 0u) atomic_add(&p_field[at], (uint)(t * (float)chord + 0.5f));
        }
}

// Another device's images (read back from it and written here) merged into this device's, pixel
// by pixel: the nearest depth, the thicknesses and field sums added (integers: the merge is exact,
// so the result does not depend on how the particles were split). has_field: the field sums too.
__kernel void splat_merge(const uint pixels, const uint has_field, __global const uint* in_depth,
                          __global const uint* in_thick, __global const uint* in_field, __global uint* depth,
                          __global uint* thickness, __global uint* field_sum) {
    const uint n = pixels, with_field = has_field;
    __global const uint* const p_in_depth = in_depth;
    __global const uint* const p_in_thick = in_thick;
    __global const uint* const p_in_field = in_field;
    __global uint* const p_depth = depth;
    __global uint* const p_thick = thickness;
    __global uint* const p_field = field_sum;
    const uint i = get_global_id(0);
    if (i >= n) return;
    p_depth[i] = min(p_depth[i], p_in_depth[i]);
    p_thick[i] += p_in_thick[i];
    if (with_field != 0u) p_field[i] += p_in_field[i];
}
