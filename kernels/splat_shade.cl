// Screen-space fluid rendering, after the splats (host/src/render/splat.cpp): the devices' depth
// and thickness images merged on the shading device (nearest depth, summed thickness: splat_merge
// in splat.cl), then there: the depth smoothed by a bilateral filter (splat_smooth, one axis per launch), normals
// taken from the smoothed depth, and the water shaded (splat_shade) with Fresnel reflection of the
// sky and the ground, refraction of what lies behind (solids, ground, sky), Beer-Lambert absorption
// by the thickness, and a sun's highlight. A pixel a launch each; images are row-major from the top.
// Depths are floats' bits (all ones: nothing), along the camera's forward axis.
#define SPLAT_EMPTY 0xffffffffu
#include "shared.h"
#include "colour_map.h"

// The splats' sums as the filter and the shading take them: the thickness in metres (counts times
// `unit`), and with a field (by_field) each pixel's chord-weighted mean t, field / thickness (-1
// where no water was drawn).
__kernel void splat_prepare(const uint pixels, const float unit, const uint by_field, __global const uint* counts,
                            __global const uint* field_sum, __global float* thickness, __global float* field) {
    const uint n = pixels, with_field = by_field;
    const float u = unit;
    __global const uint* const p_counts = counts;
    __global const uint* const p_sum = field_sum;
    __global float* const p_thick = thickness;
    __global float* const p_field = field;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const uint c = p_counts[i];
    p_thick[i] = (float)c * u;
    if (with_field != 0u) p_field[i] = c > 0u ? (float)p_sum[i] / (float)c : -1.0f;
}

// One pass of the bilateral filter along x (axis 0) or y (axis 1): neighbours within `world`
// metres (in pixels at the pixel's depth, at most max_px) weighted by a Gaussian of their distance,
// those whose depth is more than `gap` from this pixel's left out (another sheet of water, or the
// far side of a silhouette). A soft range weight would blur only along lines of equal depth and
// streak a surface seen at a grazing angle; with a cut-off the filter of a plane is the plane.
// The thickness (float metres) is blurred by the same Gaussian, pixels without water counting as
// none, so it loses the lattice's ripple and fades at the rim.
__kernel void splat_smooth(const uint2 size, const float4 view, const uint axis, const uint max_px,
                           __global const uint* in, __global const float* in_thick, __global uint* out,
                           __global float* out_thick) {
    const int w = (int)size.x, h = (int)size.y;
    const float scale = view.x, world = view.y, gap = view.z;
    const int dx = axis == 0u ? 1 : 0, dy = axis == 0u ? 0 : 1;
    const int limit = (int)max_px;
    __global const uint* const p_in = in;
    __global const float* const p_in_thick = in_thick;
    __global uint* const p_out = out;
    __global float* const p_out_thick = out_thick;
    const int i = (int)get_global_id(0);
    if (i >= w * h) return;
    const uint centre = p_in[i];
    const float radius = centre == SPLAT_EMPTY ? 0.0f : fmin((float)limit, scale * world / as_float(centre));
    const int reach = (int)radius;
    if (reach < 1) {
        p_out[i] = centre;
        p_out_thick[i] = p_in_thick[i];
        return;
    }
    const int x = i % w, y = i / w;
    const float zc = as_float(centre);
    const float inv_s = 1.0f / (2.0f * 0.25f * radius * radius);
    float sum = 0.0f, weights = 0.0f, thick = 0.0f, all = 0.0f;
    for (int k = -reach; k <= reach; ++k) {
        const int xx = x + k * dx, yy = y + k * dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        const int at = yy * w + xx;
        const float wt = exp(-(float)(k * k) * inv_s);
        thick += wt * p_in_thick[at];
        all += wt;
        const uint b = p_in[at];
        if (b == SPLAT_EMPTY) continue;
        const float z = as_float(b);
        if (fabs(z - zc) > gap) continue;
        sum += wt * z;
        weights += wt;
    }
    p_out[i] = as_uint(sum / weights);
    p_out_thick[i] = thick / all;
}

typedef struct {
    float3 right, up, forward, eye;  // the camera; eye in world coordinates
    float scale, cx, cy;
    int w, h;
    float3 sky_up;                   // the world's up (against gravity)
    float height;                    // the eye above the ground plane
    float tile;                      // the ground's checker tile edge, m
    float3 sun;
} Shading;

inline float3 unpack_rgb(const uint c) {
    return (float3)((float)(c & 0xffu), (float)((c >> 8) & 0xffu), (float)((c >> 16) & 0xffu)) * (1.0f / 255.0f);
}

inline uint pack_rgb(const float3 c) {
    const float3 v = clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f;
    return (uint)v.x | ((uint)v.y << 8) | ((uint)v.z << 16) | (255u << 24);
}

inline float3 camera_ray(const Shading* s, const float px, const float py) {  // unnormalised, forward part 1
    return (px - s->cx) / s->scale * s->right + (s->cy - py) / s->scale * s->up + s->forward;
}

// The sky: a haze at the horizon to blue overhead, and the sun; below the horizon the ground
// plane, a light checker fading into the haze with distance. *t: the distance to the ground, or 0.
inline float3 environment(const Shading* s, const float3 dir, float* t) {
    const float3 haze = (float3)(0.86f, 0.90f, 0.95f), zenith = (float3)(0.30f, 0.50f, 0.80f);
    const float elevation = dot(dir, s->sky_up);
    *t = 0.0f;
    if (elevation < -1e-4f && s->height > 0.0f) {
        const float dist = s->height / -elevation;
        const float3 p = s->eye + dist * dir;
        // Checker coordinates in the plane: two axes perpendicular to up.
        const float3 helper = fabs(s->sky_up.x) < 0.9f ? (float3)(1.0f, 0.0f, 0.0f) : (float3)(0.0f, 1.0f, 0.0f);
        const float3 e1 = normalize(cross(s->sky_up, helper)), e2 = cross(s->sky_up, e1);
        const int cu = (int)floor(dot(p, e1) / s->tile), cv = (int)floor(dot(p, e2) / s->tile);
        const float3 tile = ((cu + cv) & 1) ? (float3)(0.74f, 0.71f, 0.66f) : (float3)(0.64f, 0.61f, 0.57f);
        const float lit = 0.55f + 0.45f * fmax(dot(s->sun, s->sky_up), 0.0f);
        const float fog = exp(-dist / (60.0f * s->tile));
        *t = dist;
        return mix(haze, tile * lit, fog);
    }
    const float e = clamp(elevation, 0.0f, 1.0f);
    const float3 sky = mix(haze, zenith, pow(e, 0.55f));
    const float sun = pow(fmax(dot(dir, s->sun), 0.0f), 900.0f);
    return sky + sun * (float3)(1.0f, 0.95f, 0.85f);
}

// What a pixel shows without water: the solids' colour where they were drawn, else the ground or
// the sky. *depth: along forward, or empty (the sky).
inline float3 behind(const Shading* s, const int x, const int y, __global const uint* solid_depth,
                     __global const uint* solid_colour, uint* depth) {
    const int cx = clamp(x, 0, s->w - 1), cy = clamp(y, 0, s->h - 1);
    const int at = cy * s->w + cx;
    const uint sd = solid_depth[at];
    if (sd != SPLAT_EMPTY) {
        *depth = sd;
        return unpack_rgb(solid_colour[at]);
    }
    const float3 ray = camera_ray(s, (float)cx + 0.5f, (float)cy + 0.5f);
    const float len = length(ray);
    float t;
    const float3 c = environment(s, ray / len, &t);
    *depth = t > 0.0f ? as_uint(t / len) : SPLAT_EMPTY;
    return c;
}

// A point of the water's surface in camera coordinates (right, up, forward) from its depth.
inline float3 view_point(const Shading* s, const int x, const int y, const float z) {
    return z * (float3)(((float)x + 0.5f - s->cx) / s->scale, (s->cy - (float)y - 0.5f) / s->scale, 1.0f);
}

// The surface's step to the next pixel along (dx, dy): the central difference, or where a
// neighbour is missing or beyond `gap` in depth (a silhouette), the one-sided difference on the
// side whose depth is closer; false when neither neighbour has water.
inline bool surface_step(const Shading* s, __global const uint* depth, const int x, const int y, const int dx,
                         const int dy, const float3 here, const float gap, float3* d) {
    const int xa = x + dx, ya = y + dy, xb = x - dx, yb = y - dy;
    const bool a = xa >= 0 && ya >= 0 && xa < s->w && ya < s->h && depth[ya * s->w + xa] != SPLAT_EMPTY;
    const bool b = xb >= 0 && yb >= 0 && xb < s->w && yb < s->h && depth[yb * s->w + xb] != SPLAT_EMPTY;
    if (!a && !b) return false;
    const float3 pa = a ? view_point(s, xa, ya, as_float(depth[ya * s->w + xa])) : here;
    const float3 pb = b ? view_point(s, xb, yb, as_float(depth[yb * s->w + xb])) : here;
    const float3 da = pa - here, db = here - pb;
    if (a && b && fabs(da.z) < gap && fabs(db.z) < gap)
        *d = 0.5f * (da + db);
    else
        *d = (!b || (a && fabs(da.z) <= fabs(db.z))) ? da : db;
    return true;
}

// The picture: water where its (smoothed) depth is in front of the solids, else what lies behind.
// view: (scale, cx, cy, refraction offset in pixels at full thickness); sky: (world up, eye height);
// ground: (sun direction, checker tile); absorb: per-channel absorption per metre (thickness in
// metres, smoothed); tint: the colour deep water tends to; edge: the thickness (m) over which
// water goes from clear to opaque at its rim (x), of a full refraction offset (y), and the depth
// step (m) that is a silhouette rather than a slope (z). by_field: the water coloured by `field`
// (each pixel's t in [0, 1] through colour_map.h; below 0: none), nearly opaque, lit by the sun and
// with a weaker reflection, so that the colour reads as the field's and not the background's.
__kernel void splat_shade(const uint2 size, const float4 view, const float4 right, const float4 up,
                          const float4 forward, const float4 eye, const float4 sky, const float4 ground,
                          const float4 absorb, const float4 tint, const float4 edge, const uint by_field,
                          __global const uint* water, __global const float* thickness,
                          __global const uint* solid_depth, __global const uint* solid_colour,
                          __global const float* field, __global uint* colour, __global uint* depth) {
    Shading s;
    s.right = right.xyz;
    s.up = up.xyz;
    s.forward = forward.xyz;
    s.eye = eye.xyz;
    s.scale = view.x;
    s.cx = view.y;
    s.cy = view.z;
    s.w = (int)size.x;
    s.h = (int)size.y;
    s.sky_up = sky.xyz;
    s.height = sky.w;
    s.sun = ground.xyz;
    s.tile = ground.w;
    const float refract_px = view.w;
    const float3 sigma = absorb.xyz, deep = tint.xyz;
    const float rim = edge.x, full = edge.y, gap = edge.z;
    __global const uint* const p_water = water;
    __global const float* const p_thick = thickness;
    __global const uint* const p_sd = solid_depth;
    __global const uint* const p_sc = solid_colour;
    __global const float* const p_field = field;
    const uint coloured = by_field;
    __global uint* const p_colour = colour;
    __global uint* const p_depth = depth;
    const int i = (int)get_global_id(0);
    if (i >= s.w * s.h) return;
    const int x = i % s.w, y = i / s.w;
    uint back_depth;
    const float3 back = behind(&s, x, y, p_sd, p_sc, &back_depth);
    const uint wd = p_water[i];
    if (wd == SPLAT_EMPTY || (p_sd[i] != SPLAT_EMPTY && p_sd[i] < wd)) {
        p_colour[i] = pack_rgb(back);
        p_depth[i] = back_depth;
        return;
    }
    // The normal from the depth image, in camera coordinates, turned to face the eye.
    const float3 here = view_point(&s, x, y, as_float(wd));
    float3 ddx, ddy, n = (float3)(0.0f, 0.0f, -1.0f);
    if (surface_step(&s, p_water, x, y, 1, 0, here, gap, &ddx) && surface_step(&s, p_water, x, y, 0, 1, here, gap, &ddy)) {
        const float3 c = cross(ddx, ddy);
        const float len = length(c);
        if (len > 0.0f) n = c / len;
        if (dot(n, here) > 0.0f) n = -n;
    }
    const float3 nw = n.x * s.right + n.y * s.up + n.z * s.forward;
    const float3 ray = normalize(camera_ray(&s, (float)x + 0.5f, (float)y + 0.5f));
    const float cos_i = clamp(-dot(ray, nw), 0.0f, 1.0f);
    const float fresnel = 0.02f + 0.98f * pown(1.0f - cos_i, 5);
    const float3 mirror = ray - 2.0f * dot(ray, nw) * nw;
    float t;
    const float3 reflected = environment(&s, mirror, &t);
    // Through the water: the background displaced along the normal, more where the water is thicker.
    const float thick = p_thick[i];
    const float shift = refract_px * fmin(thick / full, 1.0f);
    uint ignored;
    const float3 seen = behind(&s, (int)floor((float)x + 0.5f + n.x * shift), (int)floor((float)y + 0.5f - n.y * shift),
                               p_sd, p_sc, &ignored);
    const float3 kept = exp(-sigma * thick);
    // The light the water scatters back is brighter where its surface faces the sun (the shape
    // reads even where the reflection is only haze).
    const float facing = 0.55f + 0.45f * fmax(dot(nw, s.sun), 0.0f);
    const float3 through = seen * kept + facing * deep * (1.0f - kept);
    float3 c = mix(through, reflected, fresnel);
    if (coloured != 0u) {
        float r, g, b;
        clsph_colour_map(p_field[i], &r, &g, &b);
        const float3 base = (float3)(r, g, b);
        const float lit = 0.6f + 0.4f * fmax(dot(nw, s.sun), 0.0f);
        c = mix(base * lit, reflected, 0.35f * fresnel);
    }
    const float glint = dot(mirror, s.sun);
    c += (0.9f * pow(fmax(glint, 0.0f), 180.0f) + 0.12f * pow(fmax(glint, 0.0f), 12.0f)) * (float3)(1.0f, 0.97f, 0.9f);
    // A single drop's rim is clear: fade to the background over the first `rim` of thickness.
    c = mix(back, c, 1.0f - exp(-thick / rim));
    p_colour[i] = pack_rgb(c);
    p_depth[i] = wd;
}
