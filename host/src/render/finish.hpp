// The last steps of an image, on the device that shows it (kernels/render_finish.cl): the other
// devices' images merged in by depth, the walls' lines drawn with the depth test, the picture
// packed as RGB over the background; only the RGB bytes are read back (2.7 MB at 1280 x 720,
// against 7.4 MB of depth and colour and the host's loops over every pixel before).
#pragma once
#include "cl/device.hpp"
#include "clsph/render.hpp"
#include "render/renderer.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace clsph::render {

class Finisher {
public:
    explicit Finisher(cl_rt::Device& device);
    // `other` (another device's image, read back) merged into `target` (an image on this device).
    void merge(const RenderTarget& target, const DepthImage& other);
    // Lines drawn into `target` in `rgb`, then the picture read back: the colour where something was
    // drawn, `background` elsewhere; every_pixel: the colour everywhere.
    Image finish(const RenderTarget& target, const std::vector<LinePixel>& lines, std::array<std::uint8_t, 3> rgb,
                 std::array<std::uint8_t, 3> background, bool every_pixel);

private:
    cl_rt::Device& device_;
    cl::Kernel merge_k_, lines_k_, rgb_k_;
    std::size_t wg_;
    cl_rt::Buffer in_depth_, in_colour_, lines_, rgb_;  // kept from frame to frame
};

}  // namespace clsph::render
