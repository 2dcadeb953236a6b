// The last steps of an image on the device that shows it (host/src/render/finish.cpp): other
// devices' images merged in by depth, the walls' lines drawn with the depth test, and the picture
// packed as 8-bit RGB over a background, so that only the finished picture is read back.
// Depths are floats' bits (all ones: nothing); colours RGBA8 packed, R lowest.
#define FINISH_EMPTY 0xffffffffu

// Another device's image merged into this one: where it is nearer, its depth and colour (ties keep
// this one's: the images are merged in the devices' order, the first device's first).
__kernel void finish_merge(const uint pixels, __global const uint* in_depth, __global const uint* in_colour,
                           __global uint* depth, __global uint* colour) {
    const uint n = pixels;
    __global const uint* const p_in_depth = in_depth;
    __global const uint* const p_in_colour = in_colour;
    __global uint* const p_depth = depth;
    __global uint* const p_colour = colour;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const uint d = p_in_depth[i];
    if (d < p_depth[i]) {
        p_depth[i] = d;
        p_colour[i] = p_in_colour[i];
    }
}

// The lines' pixels (index, depth bits: render/renderer.hpp line_pixels), each drawn where it is
// not behind what is there. Pixels of two lines may meet; both draw `rgba`, so the colour is the
// same whichever wins (a pixel is the lines' colour when any of them is in front of what was there).
__kernel void finish_lines(const uint count, const uint rgba, __global const uint2* pixels, __global uint* depth,
                           __global uint* colour) {
    const uint n = count, c = rgba;
    __global const uint2* const p_pixels = pixels;
    __global uint* const p_depth = depth;
    __global uint* const p_colour = colour;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const uint2 px = p_pixels[i];
    if (px.y <= p_depth[px.x]) {
        p_colour[px.x] = c;
        p_depth[px.x] = px.y;  // drawn (finish_rgb); any of the lines' depths here marks it so
    }
}

// RGB bytes: the colour where something was drawn, else `background` (RGBA8 packed); with
// every_pixel the colour everywhere (the splats' shading colours every pixel, sky included).
__kernel void finish_rgb(const uint pixels, const uint background, const uint every_pixel, __global const uint* depth,
                         __global const uint* colour, __global uchar* rgb) {
    const uint n = pixels, back = background, all = every_pixel;
    __global const uint* const p_depth = depth;
    __global const uint* const p_colour = colour;
    __global uchar* const p_rgb = rgb;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const uint c = (all != 0u || p_depth[i] != FINISH_EMPTY) ? p_colour[i] : back;
    p_rgb[3 * i] = (uchar)(c & 0xffu);
    p_rgb[3 * i + 1] = (uchar)((c >> 8) & 0xffu);
    p_rgb[3 * i + 2] = (uchar)((c >> 16) & 0xffu);
}
