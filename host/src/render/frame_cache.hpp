// What a run's images are drawn with, kept from frame to frame on each device: the splat pass,
// the shading and the rasteriser (their kernels and pixel buffers), and the solid boxes'
// triangles, uploaded once. Without it every image allocated, filled and released some forty
// megabytes of buffers and uploaded the boxes again (docs/surfaces.md, BENCHMARKS.md). Owned by the
// Simulation (simulation/impl.hpp), which also owns the devices and outlives it.
#pragma once
#include "cl/device.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "render/finish.hpp"
#include "render/renderer.hpp"
#include "render/splat.hpp"

#include <map>
#include <memory>

namespace clsph::render {

class FrameCache {
public:
    Splatter& splatter(cl_rt::Device& device, const device::Grid& grid);
    SplatShader& shader(cl_rt::Device& device);
    Renderer& renderer(cl_rt::Device& device);
    Finisher& finisher(cl_rt::Device& device);
    // The solid boxes as a layer on `device` (uploaded on the first call; a run's boxes do not change).
    const UploadedLayer& boxes(cl_rt::Device& device, const std::vector<SolidBox>& boxes);

private:
    struct PerDevice {
        std::unique_ptr<Splatter> splatter;
        std::unique_ptr<SplatShader> shader;
        std::unique_ptr<Renderer> renderer;
        std::unique_ptr<Finisher> finisher;
        std::unique_ptr<UploadedLayer> boxes;
    };
    std::map<const cl_rt::Device*, PerDevice> per_device_;
};

}  // namespace clsph::render
