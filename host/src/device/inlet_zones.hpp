// Inlet buffers on one device (kernels/inlets.cl, scene/open_boundaries.hpp): the inlets' boxes,
// directions and profiles, the launch that imposes the buffer's velocity (after the force pass,
// and before the drift where a speed changes in time), and the writing of an inlet's new particles
// into a block of particle arrays (the exchange's inbox).
#pragma once
#include "cl/device.hpp"
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "device/particle_arrays.hpp"
#include "device/particle_store.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace clsph::device {

class InletZones {
public:
    InletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene);
    // The owned fluid particles in an inlet's box: direction * speeds[inlet] * factor, no
    // acceleration. After the force pass (`after_forces`) in both acceleration buffers (the last
    // pass's and this one's, ps.scratch); before the drift in ps.accel only.
    void impose(ParticleStore& ps, const std::vector<double>& speeds, bool after_forces);
    // Particles p[which[k]] into dst at [at, at + which.size()) (blocking; accelerations 0).
    void write(ParticleArrays& dst, std::size_t at, const Particles& p, const std::vector<std::size_t>& which);
    // The buffers a scene's inlets take on each device, by the names they are allocated with (the
    // memory plan).
    static std::vector<std::pair<const char*, std::size_t>> buffers(const Scene& scene);

private:
    cl_rt::Device& device_;
    const Grid& grid_;
    cl::Kernel kernel_;
    cl_rt::Buffer boxes_, factors_, speeds_;
    std::vector<float> speeds_written_;  // what speeds_ holds (NaN: nothing yet)
    std::size_t inlets_ = 0, wg_ = 64;
};

}  // namespace clsph::device
