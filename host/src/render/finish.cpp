#include "render/finish.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

namespace clsph::render {
namespace {

std::uint32_t packed(std::array<std::uint8_t, 3> rgb) {
    return rgb[0] | (std::uint32_t{rgb[1]} << 8) | (std::uint32_t{rgb[2]} << 16) | (255u << 24);
}

}  // namespace

Finisher::Finisher(cl_rt::Device& device) : device_(device), wg_(device.work_group_size(64)) {
    merge_k_ = device.kernel("render_finish.cl", "finish_merge");
    lines_k_ = device.kernel("render_finish.cl", "finish_lines");
    rgb_k_ = device.kernel("render_finish.cl", "finish_rgb");
}

void Finisher::merge(const RenderTarget& target, const DepthImage& other) {
    const std::size_t pixels = std::size_t{target.width} * target.height;
    if (other.width != target.width || other.height != target.height || other.depth.size() != pixels)
        throw Error("render: the devices' images differ in size");
    if (pixels == 0) return;
    keep_buffer(device_, in_depth_, pixels * sizeof(cl_uint), "render merged depth");
    keep_buffer(device_, in_colour_, pixels * sizeof(cl_uint), "render merged colour");
    device_.write(in_depth_, other.depth.data(), pixels);
    device_.write(in_colour_, other.colour.data(), pixels);
    cl_rt::set_args(merge_k_, cl_rt::checked_uint(pixels), in_depth_, in_colour_, *target.depth, *target.colour);
    device_.launch("render.merge", merge_k_, pixels, wg_);
}

Image Finisher::finish(const RenderTarget& target, const std::vector<LinePixel>& lines, std::array<std::uint8_t, 3> rgb,
                       std::array<std::uint8_t, 3> background, bool every_pixel) {
    const std::size_t pixels = std::size_t{target.width} * target.height;
    Image out;
    out.width = target.width;
    out.height = target.height;
    out.rgb.resize(3 * pixels);
    if (pixels == 0) return out;
    if (!lines.empty()) {
        keep_buffer(device_, lines_, lines.size() * 2 * sizeof(cl_uint), "render line pixels");
        std::vector<cl_uint> words(2 * lines.size());
        for (std::size_t k = 0; k < lines.size(); ++k) {
            words[2 * k] = lines[k].index;
            words[2 * k + 1] = lines[k].depth;
        }
        device_.write(lines_, words.data(), words.size());
        cl_rt::set_args(lines_k_, cl_rt::checked_uint(lines.size()), cl_uint{packed(rgb)}, lines_, *target.depth, *target.colour);
        device_.launch("render.lines", lines_k_, lines.size(), wg_);
    }
    keep_buffer(device_, rgb_, 3 * pixels, "render rgb");
    cl_rt::set_args(rgb_k_, cl_rt::checked_uint(pixels), cl_uint{packed(background)}, cl_uint{every_pixel ? 1u : 0u}, *target.depth,
                    *target.colour, rgb_);
    device_.launch("render.rgb", rgb_k_, pixels, wg_);
    device_.read(rgb_, out.rgb.data(), out.rgb.size());
    return out;
}

}  // namespace clsph::render
