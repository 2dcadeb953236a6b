// Images coloured by a particle field (ImageStyle by_speed, by_pressure; kernels/render_field.cl):
// the field's range over the fluid the devices own (or the style's), and, on one device, the field
// at the vertices of a mesh there, as t in [0, 1] for the colour map (kernels/colour_map.h).
#pragma once
#include "cl/device.hpp"
#include "clsph/render.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "multi/slab_driver.hpp"

#include <array>
#include <cstdint>

namespace clsph::render {

// The kernels' mode of a style: 0 none, 1 speed, 2 pressure.
std::uint32_t field_mode(SurfaceColour colour);

// The range the colour map spans: the style's where both ends are given (finite), else found on
// the devices (speeds: 0 to the greatest; pressures: least to greatest; an empty fluid: 0 to 0).
std::array<double, 2> field_range(multi::SlabDriver& driver, const device::Grid& grid, const ImageStyle& style);

class FieldSampler {
public:
    FieldSampler(cl_rt::Device& device, const device::Grid& grid, const std::string& point_options);
    // The field's least and greatest value over the fluid particles `store` owns (NaN, NaN: none).
    std::array<double, 2> bounds(std::uint32_t mode, const SphParams& sp, const device::ParticleStore& store);
    // Each of `vertices` float4 points (world coordinates) its field's Shepard average from the
    // particles of `store` (owned and ghosts, through `cells`), mapped onto [0, 1] by `range`; -1
    // where no fluid is within the support.
    cl_rt::Buffer vertex_values(std::uint32_t mode, const SphParams& sp, const std::array<double, 2>& range,
                                const cl_rt::Buffer& points, std::size_t vertices, const device::ParticleStore& store,
                                const device::CellPipeline& cells);

private:
    cl_rt::Device& device_;
    const device::Grid& grid_;
    cl::Kernel bounds_k_, vertex_k_;
    std::size_t wg_;
};

}  // namespace clsph::render
