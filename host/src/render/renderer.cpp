#include "render/renderer.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace clsph::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The kernel's Camera struct (kernels/render.cl), as laid out by OpenCL C.
struct KernelCamera {
    cl_float4 eye, right, up, forward;
    cl_float scale, cx, cy;
    cl_uint width, height;
    cl_uint pad[3];  // the struct's size rounds up to its float4 alignment
};
static_assert(sizeof(KernelCamera) == 96, "matches kernels/render.cl's Camera");

using V = std::array<double, 3>;
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V cross(const V& a, const V& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
V unit(const V& a) {
    const double l = std::sqrt(dot(a, a));
    return {a[0] / l, a[1] / l, a[2] / l};
}


}  // namespace

CameraBasis camera_basis(const CameraView& c) {
    CameraBasis b;
    b.eye = c.eye;
    b.forward = unit(sub(c.target, c.eye));
    b.right = unit(cross(b.forward, c.up));
    b.up = cross(b.right, b.forward);
    b.scale = 0.5 * c.height / std::tan(0.5 * c.fov_deg * kPi / 180.0);
    b.cx = 0.5 * c.width;
    b.cy = 0.5 * c.height;
    return b;
}

Renderer::Renderer(cl_rt::Device& device) : device_(device), wg_(device.work_group_size(64)) {
    const std::string opts = device.quirks().atomic_min_unreliable ? "-DCLSPH_DEPTH_BY_CAS" : "";
    depth_k_ = device.kernel("render.cl", "render_depth", opts);
    shade_k_ = device.kernel("render.cl", "render_shade", opts);
    shade_field_k_ = device.kernel("render.cl", "render_shade_field", opts);
    no_live_ = device.alloc(4 * sizeof(cl_uint), "render triangle counts");
    device.fill(no_live_, cl_uint{0}, 4);
}

UploadedLayer Renderer::upload(const Layer& layer) {
    UploadedLayer u;
    u.colour = layer.colour;
    if (layer.triangles.empty()) return u;
    const auto& m = *layer.mesh;
    std::vector<float> p(4 * m.positions.size()), n(4 * m.positions.size(), 0.0f);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        std::memcpy(&p[4 * v], m.positions[v].data(), 12);
        if (!m.normals.empty()) std::memcpy(&n[4 * v], m.normals[v].data(), 12);
    }
    std::vector<cl_uint> t(3 * layer.triangles.size());
    for (std::size_t k = 0; k < layer.triangles.size(); ++k)
        for (std::size_t c = 0; c < 3; ++c) t[3 * k + c] = m.triangles[layer.triangles[k]][c];
    u.positions = device_.alloc(p.size() * sizeof(float), "render positions");
    u.normals = device_.alloc(n.size() * sizeof(float), "render normals");
    u.triangles = device_.alloc(t.size() * sizeof(cl_uint), "render triangles");
    device_.write(u.positions, p.data(), p.size());
    device_.write(u.normals, n.data(), n.size());
    device_.write(u.triangles, t.data(), t.size());
    u.count = layer.triangles.size();
    return u;
}

DepthImage Renderer::draw(const CameraView& camera, const std::vector<Layer>& layers) {
    std::vector<UploadedLayer> up;
    std::vector<DeviceLayer> on_device;
    for (const auto& layer : layers) {
        if (layer.triangles.empty()) continue;
        up.push_back(upload(layer));
    }
    for (const auto& u : up) on_device.push_back(u.layer());
    return draw(camera, on_device);
}

DepthImage Renderer::draw(const CameraView& camera, const std::vector<DeviceLayer>& layers) {
    const RenderTarget t = render(camera, layers);
    return read_depth_image(device_, *t.depth, *t.colour, t.width, t.height);
}

RenderTarget Renderer::render(const CameraView& camera, const std::vector<DeviceLayer>& layers) {
    const CameraBasis b = camera_basis(camera);
    KernelCamera kc{};
    kc.eye = float4_of(b.eye);
    kc.right = float4_of(b.right);
    kc.up = float4_of(b.up);
    kc.forward = float4_of(b.forward);
    kc.scale = static_cast<float>(b.scale);
    kc.cx = static_cast<float>(b.cx);
    kc.cy = static_cast<float>(b.cy);
    kc.width = camera.width;
    kc.height = camera.height;
    const cl_float4 view{{kc.scale, kc.cx, kc.cy, 0.0f}};
    const cl_uint2 size{{camera.width, camera.height}};
    const std::size_t pixels = std::size_t{camera.width} * camera.height;
    keep_buffer(device_, depth_, pixels * sizeof(cl_uint), "render depth");
    keep_buffer(device_, colour_, pixels * sizeof(cl_uint), "render colour");
    auto& depth = depth_;
    auto& colour = colour_;
    device_.fill(depth, cl_uint(0xffffffffu), pixels);
    device_.fill(colour, cl_uint(0), pixels);
    for (const auto& u : layers) {
        if (u.count == 0) continue;
        const cl_rt::Buffer& live = u.live ? *u.live : no_live_;
        const cl_uint live_at = u.live ? u.live_at : 4u;
        cl_rt::set_args(depth_k_, cl_rt::checked_uint(u.count), live, live_at, kc.eye, kc.right, kc.up, kc.forward, view, size, *u.positions,
                        *u.triangles, depth);
        device_.launch("render.depth", depth_k_, u.count, wg_);
    }
    for (const auto& u : layers) {  // every layer's depth first, then the colours
        if (u.count == 0) continue;
        const cl_float4 base{{u.colour[0], u.colour[1], u.colour[2], 1.0f}};
        const cl_rt::Buffer& live = u.live ? *u.live : no_live_;
        const cl_uint live_at = u.live ? u.live_at : 4u;
        if (u.values) {
            cl_rt::set_args(shade_field_k_, cl_rt::checked_uint(u.count), live, live_at, kc.eye, kc.right, kc.up, kc.forward, view, size,
                            base, *u.positions, *u.normals, *u.triangles, *u.values, depth, colour);
            device_.launch("render.shade", shade_field_k_, u.count, wg_);
            continue;
        }
        cl_rt::set_args(shade_k_, cl_rt::checked_uint(u.count), live, live_at, kc.eye, kc.right, kc.up, kc.forward, view, size, base,
                        *u.positions, *u.normals, *u.triangles, depth, colour);
        device_.launch("render.shade", shade_k_, u.count, wg_);
    }
    return {&depth_, &colour_, camera.width, camera.height};
}

void keep_buffer(cl_rt::Device& device, cl_rt::Buffer& b, std::size_t bytes, const char* what) {
    if (b.bytes() >= bytes) return;
    b = {};
    b = device.alloc(bytes, what);
}

cl_float4 float4_of(const std::array<double, 3>& v, double w) {
    return {{static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]), static_cast<float>(w)}};
}

DepthImage read_depth_image(cl_rt::Device& device, const cl_rt::Buffer& depth, const cl_rt::Buffer& colour,
                            std::uint32_t width, std::uint32_t height) {
    const std::size_t pixels = std::size_t{width} * height;
    DepthImage out;
    out.width = width;
    out.height = height;
    out.depth.resize(pixels);
    out.colour.resize(pixels);
    device.read(depth, out.depth.data(), pixels);
    device.read(colour, out.colour.data(), pixels);
    return out;
}

DepthImage composite(const std::vector<DepthImage>& images) {
    if (images.empty()) throw Error("render: nothing to composite");
    DepthImage out = images.front();
    for (std::size_t i = 1; i < images.size(); ++i) {
        const auto& im = images[i];
        for (std::size_t p = 0; p < out.depth.size(); ++p)
            if (im.depth[p] < out.depth[p]) {
                out.depth[p] = im.depth[p];
                out.colour[p] = im.colour[p];
            }
    }
    return out;
}

std::vector<LinePixel> line_pixels(const CameraView& camera, const std::vector<std::array<Vec3, 2>>& lines) {
    const CameraBasis b = camera_basis(camera);
    std::vector<LinePixel> out;
    for (const auto& line : lines) {
        const V d0 = sub(line[0], b.eye), d1 = sub(line[1], b.eye);
        const double z0 = dot(d0, b.forward), z1 = dot(d1, b.forward);
        if (z0 <= 1e-6 || z1 <= 1e-6) continue;
        const double x0 = b.cx + b.scale * dot(d0, b.right) / z0, y0 = b.cy - b.scale * dot(d0, b.up) / z0;
        const double x1 = b.cx + b.scale * dot(d1, b.right) / z1, y1 = b.cy - b.scale * dot(d1, b.up) / z1;
        const int steps = static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))) + 1;
        if (steps > 1 << 16) continue;
        for (int s = 0; s <= steps; ++s) {
            const double t = static_cast<double>(s) / steps;
            const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
            const double z = 1.0 / ((1 - t) / z0 + t / z1);
            if (x < 0 || y < 0 || x >= camera.width || y >= camera.height) continue;
            const float zf = static_cast<float>(z * 0.999);  // a little in front of a face the line lies on
            LinePixel px;
            px.index = static_cast<std::uint32_t>(static_cast<std::size_t>(y) * camera.width + static_cast<std::size_t>(x));
            std::memcpy(&px.depth, &zf, 4);
            out.push_back(px);
        }
    }
    return out;
}

void draw_lines(DepthImage& im, const CameraView& camera, const std::vector<std::array<Vec3, 2>>& lines,
                std::array<std::uint8_t, 3> rgb) {
    const std::uint32_t packed = rgb[0] | (std::uint32_t{rgb[1]} << 8) | (std::uint32_t{rgb[2]} << 16) | (255u << 24);
    for (const auto& px : line_pixels(camera, lines))
        if (px.depth <= im.depth[px.index]) {
            im.depth[px.index] = px.depth;
            im.colour[px.index] = packed;
        }
}

Image to_rgb(const DepthImage& im, std::array<std::uint8_t, 3> background) {
    Image out;
    out.width = im.width;
    out.height = im.height;
    out.rgb.resize(std::size_t{3} * im.width * im.height);
    for (std::size_t p = 0; p < im.depth.size(); ++p) {
        const bool hit = im.depth[p] != 0xffffffffu;
        for (std::size_t c = 0; c < 3; ++c)
            out.rgb[3 * p + c] = hit ? static_cast<std::uint8_t>((im.colour[p] >> (8 * c)) & 0xffu) : background[c];
    }
    return out;
}

}  // namespace clsph::render
