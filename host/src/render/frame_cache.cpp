#include "render/frame_cache.hpp"

#include "render/scene_image.hpp"

namespace clsph::render {

Splatter& FrameCache::splatter(cl_rt::Device& device, const device::Grid& grid) {
    auto& s = per_device_[&device].splatter;
    if (!s) s = std::make_unique<Splatter>(device, grid);
    return *s;
}

SplatShader& FrameCache::shader(cl_rt::Device& device) {
    auto& s = per_device_[&device].shader;
    if (!s) s = std::make_unique<SplatShader>(device);
    return *s;
}

Renderer& FrameCache::renderer(cl_rt::Device& device) {
    auto& r = per_device_[&device].renderer;
    if (!r) r = std::make_unique<Renderer>(device);
    return *r;
}

Finisher& FrameCache::finisher(cl_rt::Device& device) {
    auto& f = per_device_[&device].finisher;
    if (!f) f = std::make_unique<Finisher>(device);
    return *f;
}

const UploadedLayer& FrameCache::boxes(cl_rt::Device& device, const std::vector<SolidBox>& boxes) {
    auto& up = per_device_[&device].boxes;
    if (!up) {
        const TriangleMesh mesh = box_mesh(boxes);
        Layer layer{&mesh, {}, {0.62f, 0.60f, 0.58f}};  // scene_image.cpp kSolid
        for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) layer.triangles.push_back(t);
        up = std::make_unique<UploadedLayer>(renderer(device).upload(layer));
    }
    return *up;
}

}  // namespace clsph::render
