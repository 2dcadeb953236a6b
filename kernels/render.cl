// Triangles rasterised into a depth buffer and a colour buffer (host/src/render/). Two passes over
// the triangles, a work-item each: render_depth keeps each pixel's nearest depth with a 32-bit
// atomic_min on the float's bits (positive floats order as their bits do; 64-bit atomics are not
// portable), then render_shade writes the colour of the triangle whose depth is the pixel's. The
// camera is given as an eye, three unit axes (right, up, forward) and the image plane's scale.
typedef struct {
    float4 eye, right, up, forward;  // .w unused
    float scale;                     // pixels per unit of (x / z) on the image plane
    float cx, cy;                    // the image centre in pixels
    uint width, height;
} Camera;

inline float3 project(const Camera* c, const float3 p) {  // (pixel x, pixel y, depth)
    const float3 d = p - c->eye.xyz;
    const float z = dot(d, c->forward.xyz);
    const float iz = 1.0f / z;
    return (float3)(c->cx + c->scale * dot(d, c->right.xyz) * iz, c->cy - c->scale * dot(d, c->up.xyz) * iz, z);
}

// The pixels a triangle covers (centres inside it, top-left rule by half-open edge tests) and
// its depth there: calls PIXEL(x, y, z, w0, w1, w2).
#define RASTER(c, a, b, t, PIXEL)                                                                      \
    do {                                                                                               \
        if ((a).z <= 1e-6f || (b).z <= 1e-6f || (t).z <= 1e-6f) break; /* behind the eye */          \
        const float area = ((b).x - (a).x) * ((t).y - (a).y) - ((b).y - (a).y) * ((t).x - (a).x);   \
        if (fabs(area) < 1e-12f) break;                                                                \
        const int x0 = max(0, (int)floor(min(min((a).x, (b).x), (t).x)));                            \
        const int x1 = min((int)(c)->width - 1, (int)ceil(max(max((a).x, (b).x), (t).x)));            \
        const int y0 = max(0, (int)floor(min(min((a).y, (b).y), (t).y)));                            \
        const int y1 = min((int)(c)->height - 1, (int)ceil(max(max((a).y, (b).y), (t).y)));           \
        if (x1 < x0 || y1 < y0 || (x1 - x0 + 1) * (y1 - y0 + 1) > 1 << 20) break;                     \
        const float inv = 1.0f / area;                                                                 \
        for (int y = y0; y <= y1; ++y)                                                                 \
            for (int x = x0; x <= x1; ++x) {                                                           \
                const float px = (float)x + 0.5f, py = (float)y + 0.5f;                                \
                const float w0 = (((b).x - px) * ((t).y - py) - ((b).y - py) * ((t).x - px)) * inv;   \
                const float w1 = (((t).x - px) * ((a).y - py) - ((t).y - py) * ((a).x - px)) * inv;   \
                const float w2 = 1.0f - w0 - w1;                                                       \
                if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;                                    \
                const float z = 1.0f / (w0 / (a).z + w1 / (b).z + w2 / (t).z);                         \
                PIXEL(x, y, z, w0, w1, w2);                                                            \
            }                                                                                          \
    } while (0)

// The camera as plain vector arguments (a struct argument with float4 members is laid out
// differently by some implementations: Mesa rusticl 22.3 drew nothing with one).
inline Camera camera_of(const float4 eye, const float4 right, const float4 up, const float4 forward, const float4 view,
                        const uint2 size) {
    Camera c;
    c.eye = eye;
    c.right = right;
    c.up = up;
    c.forward = forward;
    c.scale = view.x;
    c.cx = view.y;
    c.cy = view.z;
    c.width = size.x;
    c.height = size.y;
    return c;
}

#include "depth_min.h"

__kernel void render_depth(const uint triangles, __global const uint* live, const uint live_at, const float4 eye, const float4 right, const float4 up,
                           const float4 forward, const float4 view, const uint2 size, __global const float4* pos,
                           __global const uint* tri, __global uint* depth) {
    // Every argument read before any branch (Mesa rusticl 22.3 warns that it treats argument loads
    // in control flow as uniform, and drew nothing when they were read inside the loops).
    const Camera c = camera_of(eye, right, up, forward, view, size);
    __global const float4* const p_pos = pos;
    __global const uint* const p_tri = tri;
    __global uint* const p_depth = depth;
    // The triangles there are: `triangles`, or at most that many as counted on the device
    // (live[live_at], live_at < 4: a surface's totals), read before any branch like the rest.
    const uint on_device = live[live_at & 3u];
    const uint count = live_at < 4u ? min(triangles, on_device) : triangles;
    const uint t = get_global_id(0);
    if (t >= count) return;
    const float3 a = project(&c, p_pos[p_tri[3u * t]].xyz), b = project(&c, p_pos[p_tri[3u * t + 1u]].xyz),
                 d = project(&c, p_pos[p_tri[3u * t + 2u]].xyz);
#define DEPTH_PIXEL(x, y, z, w0, w1, w2) depth_min(&p_depth[(uint)(y) * c.width + (uint)(x)], as_uint(z))
    RASTER(&c, a, b, d, DEPTH_PIXEL);
#undef DEPTH_PIXEL
}

// Lambert shading with a head light and a key light, `base` the surface's colour (0..1).
__kernel void render_shade(const uint triangles, __global const uint* live, const uint live_at, const float4 eye, const float4 right, const float4 up,
                           const float4 forward, const float4 view, const uint2 size, const float4 base,
                           __global const float4* pos, __global const float4* nrm, __global const uint* tri,
                           __global const uint* depth, __global uint* colour) {
    const Camera c = camera_of(eye, right, up, forward, view, size);  // arguments first (see render_depth)
    __global const float4* const p_pos = pos;
    __global const float4* const p_nrm = nrm;
    __global const uint* const p_tri = tri;
    __global const uint* const p_depth = depth;
    __global uint* const p_colour = colour;
    const float4 p_base = base;
    // The triangles there are: `triangles`, or at most that many as counted on the device
    // (live[live_at], live_at < 4: a surface's totals), read before any branch like the rest.
    const uint on_device = live[live_at & 3u];
    const uint count = live_at < 4u ? min(triangles, on_device) : triangles;
    const uint t = get_global_id(0);
    if (t >= count) return;
    const uint i0 = p_tri[3u * t], i1 = p_tri[3u * t + 1u], i2 = p_tri[3u * t + 2u];
    const float3 a = project(&c, p_pos[i0].xyz), b = project(&c, p_pos[i1].xyz), d = project(&c, p_pos[i2].xyz);
    const float3 n0 = p_nrm[i0].xyz, n1 = p_nrm[i1].xyz, n2 = p_nrm[i2].xyz;
    const float3 key = normalize((float3)(0.3f, -0.5f, 0.8f));
#define SHADE_PIXEL(x, y, z, w0, w1, w2)                                                         \
    do {                                                                                         \
        const uint at = (uint)(y) * c.width + (uint)(x);                                         \
        if (p_depth[at] != as_uint(z)) break;                                                      \
        float3 n = w0 * n0 + w1 * n1 + w2 * n2;                                                  \
        const float len = length(n);                                                             \
        n = len > 0.0f ? n / len : -c.forward.xyz;                                               \
        const float l = 0.25f + 0.45f * fabs(dot(n, c.forward.xyz)) + 0.35f * fmax(dot(n, key), 0.0f); \
        const float3 rgb = clamp(p_base.xyz * l, 0.0f, 1.0f);                                     \
        p_colour[at] = (uint)(rgb.x * 255.0f + 0.5f) | ((uint)(rgb.y * 255.0f + 0.5f) << 8) |   \
                     ((uint)(rgb.z * 255.0f + 0.5f) << 16) | (255u << 24);                       \
    } while (0)
    RASTER(&c, a, b, d, SHADE_PIXEL);
#undef SHADE_PIXEL
}

#include "shared.h"
#include "colour_map.h"

// The same shading with the colour taken per vertex: `values` holds each vertex's t in [0, 1] (a
// field through colour_map.h; below 0: no fluid near it, drawn in `base`), interpolated across the
// triangle with perspective-correct weights.
__kernel void render_shade_field(const uint triangles, __global const uint* live, const uint live_at, const float4 eye, const float4 right, const float4 up,
                                 const float4 forward, const float4 view, const uint2 size, const float4 base,
                                 __global const float4* pos, __global const float4* nrm, __global const uint* tri,
                                 __global const float* values, __global const uint* depth, __global uint* colour) {
    const Camera c = camera_of(eye, right, up, forward, view, size);  // arguments first (see render_depth)
    __global const float4* const p_pos = pos;
    __global const float4* const p_nrm = nrm;
    __global const uint* const p_tri = tri;
    __global const float* const p_values = values;
    __global const uint* const p_depth = depth;
    __global uint* const p_colour = colour;
    const float4 p_base = base;
    // The triangles there are: `triangles`, or at most that many as counted on the device
    // (live[live_at], live_at < 4: a surface's totals), read before any branch like the rest.
    const uint on_device = live[live_at & 3u];
    const uint count = live_at < 4u ? min(triangles, on_device) : triangles;
    const uint t = get_global_id(0);
    if (t >= count) return;
    const uint i0 = p_tri[3u * t], i1 = p_tri[3u * t + 1u], i2 = p_tri[3u * t + 2u];
    const float3 a = project(&c, p_pos[i0].xyz), b = project(&c, p_pos[i1].xyz), d = project(&c, p_pos[i2].xyz);
    const float3 n0 = p_nrm[i0].xyz, n1 = p_nrm[i1].xyz, n2 = p_nrm[i2].xyz;
    const float v0 = p_values[i0], v1 = p_values[i1], v2 = p_values[i2];
    const float3 key = normalize((float3)(0.3f, -0.5f, 0.8f));
#define FIELD_PIXEL(x, y, z, w0, w1, w2)                                                          \
    do {                                                                                         \
        const uint at = (uint)(y) * c.width + (uint)(x);                                         \
        if (p_depth[at] != as_uint(z)) break;                                                      \
        float3 n = w0 * n0 + w1 * n1 + w2 * n2;                                                  \
        const float len = length(n);                                                             \
        n = len > 0.0f ? n / len : -c.forward.xyz;                                               \
        const float l = 0.25f + 0.45f * fabs(dot(n, c.forward.xyz)) + 0.35f * fmax(dot(n, key), 0.0f); \
        /* perspective-correct: weights over depth, renormalised */                              \
        const float q0 = (w0) / a.z, q1 = (w1) / b.z, q2 = (w2) / d.z;                            \
        const float qs = q0 + q1 + q2;                                                           \
        float3 col = p_base.xyz;                                                                 \
        if (v0 >= 0.0f && v1 >= 0.0f && v2 >= 0.0f && qs > 0.0f) {                               \
            float r, g, bl;                                                                      \
            clsph_colour_map((q0 * v0 + q1 * v1 + q2 * v2) / qs, &r, &g, &bl);                   \
            col = (float3)(r, g, bl);                                                            \
        } else if (v0 >= 0.0f || v1 >= 0.0f || v2 >= 0.0f) {                                     \
            /* the vertices that have a value */                                                 \
            const float s0 = v0 >= 0.0f ? q0 : 0.0f, s1 = v1 >= 0.0f ? q1 : 0.0f, s2 = v2 >= 0.0f ? q2 : 0.0f; \
            const float ss = s0 + s1 + s2;                                                       \
            const float vv = ss > 0.0f ? (s0 * fmax(v0, 0.0f) + s1 * fmax(v1, 0.0f) + s2 * fmax(v2, 0.0f)) / ss \
                                       : fmax(fmax(v0, v1), v2);                                 \
            float r, g, bl;                                                                      \
            clsph_colour_map(vv, &r, &g, &bl);                                                   \
            col = (float3)(r, g, bl);                                                            \
        }                                                                                        \
        const float3 rgb = clamp(col * l, 0.0f, 1.0f);                                           \
        p_colour[at] = (uint)(rgb.x * 255.0f + 0.5f) | ((uint)(rgb.y * 255.0f + 0.5f) << 8) |   \
                     ((uint)(rgb.z * 255.0f + 0.5f) << 16) | (255u << 24);                       \
    } while (0)
    RASTER(&c, a, b, d, FIELD_PIXEL);
#undef FIELD_PIXEL
}
