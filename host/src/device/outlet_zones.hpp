// Outlet zones on one device (kernels/outlets.cl; docs/scenes.md, outlets): the zones of a scene's
// outlets that have one, the launch that holds their density after the force pass, and the one
// that removes the fluid past their faces after the drift. A level that follows a series is
// written for each step's time.
#pragma once
#include "cl/device.hpp"
#include "clsph/scene.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "scene/time_series.hpp"

#include <cstddef>
#include <vector>

namespace clsph::device {

class OutletZones {
public:
    OutletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene);
    // After the force pass: the density Tait's equation gives in each zone that holds a pressure
    // or a level (the level at time t where it follows a series), no drho/dt in either
    // acceleration buffer (ps.accel, and the pass's ps.scratch).
    void hold(ParticleStore& ps, double t);
    // After the drift: the fluid past each zone's face is marked to leave the domain.
    void remove_past(ParticleStore& ps);
    // The device bytes of a scene's zones (the memory plan).
    static std::size_t bytes(const Scene& scene);

private:
    cl_rt::Device& device_;
    const Grid& grid_;
    cl::Kernel hold_, remove_;
    cl_rt::Buffer zones_;
    struct Moving { std::size_t zone; scene::IntegratedSeries level; float written; };
    std::vector<Moving> moving_;  // zones whose level follows a series
    double z0_ = 0;               // the domain's min z (levels are relative to it on the device)
    float rho0_ = 0, rho0_g_ = 0, inv_b_ = 0, inv_gamma_ = 0;
    bool holds_ = false;
    std::size_t zones_count_ = 0, wg_ = 64;
};

}  // namespace clsph::device
