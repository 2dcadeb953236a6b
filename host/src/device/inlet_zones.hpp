// Inlet buffers on one device (kernels/inlets.cl, scene/open_boundaries.hpp): the inlets' boxes
// and velocities, the launch that imposes them between the force pass and the kick, and the
// writing of an inlet's new particles into a block of particle arrays (the exchange's inbox).
#pragma once
#include "cl/device.hpp"
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "device/particle_arrays.hpp"
#include "device/particle_store.hpp"

#include <cstddef>
#include <vector>

namespace clsph::device {

class InletZones {
public:
    InletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene);
    // The owned fluid particles in an inlet's box: its velocity, no acceleration.
    void impose(ParticleStore& ps);
    // Particles p[which[k]] into dst at [at, at + which.size()) (blocking; accelerations 0).
    void write(ParticleArrays& dst, std::size_t at, const Particles& p, const std::vector<std::size_t>& which);

private:
    cl_rt::Device& device_;
    const Grid& grid_;
    cl::Kernel kernel_;
    cl_rt::Buffer boxes_;
    std::size_t inlets_ = 0, wg_ = 64;
};

}  // namespace clsph::device
