#include "device/outlet_zones.hpp"

#include "cl/kernel_args.hpp"
#include "shared.h"

#include <cmath>
#include <cstddef>
#include <limits>

namespace clsph::device {

OutletZones::OutletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene)
    : device_(device), grid_(grid), wg_(device.work_group_size(64)) {
    const auto& ph = scene.physics;
    const double c0 = scene.sound_speed(), b = c0 * c0 * ph.rho0 / ph.gamma;
    z0_ = scene.domain.min[2];
    rho0_ = static_cast<float>(ph.rho0);
    rho0_g_ = static_cast<float>(ph.rho0 * -ph.gravity[2]);
    inv_b_ = static_cast<float>(1.0 / b);
    inv_gamma_ = static_cast<float>(1.0 / ph.gamma);
    std::vector<OutletZone> zones;
    for (const Outlet& o : scene.outlets) {
        if (!o.zone) continue;
        OutletZone z{};
        for (int k = 0; k < 3; ++k) {
            z.lo[k] = static_cast<float>(o.min[k] - scene.domain.min[k]);
            z.hi[k] = static_cast<float>(o.max[k] - scene.domain.min[k]);
        }
        z.axis = static_cast<cl_uint>(o.axis);
        z.upper = o.upper ? 1u : 0u;
        if (o.pressure) {  // Tait's density for it, in double here
            z.hold = 1u;
            z.value = static_cast<float>(ph.rho0 * std::pow(1.0 + *o.pressure / b, 1.0 / ph.gamma));
        } else if (o.level || !o.level_series.empty()) {
            z.hold = 2u;
            const double level = o.level ? *o.level : scene::IntegratedSeries(o.level_series).value(0.0);
            z.value = static_cast<float>(level - z0_);
            if (!o.level_series.empty()) moving_.push_back({zones.size(), scene::IntegratedSeries(o.level_series), z.value});
        }
        holds_ = holds_ || z.hold != 0u;
        zones.push_back(z);
    }
    zones_count_ = zones.size();
    if (zones.empty()) zones.push_back(OutletZone{});
    zones_ = device_.alloc(zones.size() * sizeof(OutletZone), "outlet zones");
    device_.write(zones_, zones.data(), zones.size());
    hold_ = device_.kernel("outlets.cl", "hold_outlets", grid_.kernel_options());
    remove_ = device_.kernel("outlets.cl", "remove_past_outlets", grid_.kernel_options());
}

std::size_t OutletZones::bytes(const Scene& scene) {
    std::size_t n = 0;
    for (const Outlet& o : scene.outlets) n += o.zone ? 1 : 0;
    return n * sizeof(OutletZone);
}

void OutletZones::hold(ParticleStore& ps, double t) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0 || !holds_) return;
    for (auto& m : moving_) {
        const float value = static_cast<float>(m.level.value(t) - z0_);
        if (value == m.written) continue;
        // The zone's `value`, in floats from the buffer's start (the pattern is copied at once).
        device_.fill(zones_, value, 1, (m.zone * sizeof(OutletZone) + offsetof(OutletZone, value)) / sizeof(float));
        m.written = value;
    }
    cl_rt::set_args(hold_, ps.ranges.first_owned(), ps.ranges.end_owned(), grid_.params(), zones_count_, zones_, rho0_, rho0_g_,
                    inv_b_, inv_gamma_, ps.pos, ps.id, ps.velrho, ps.accel, ps.scratch);
    device_.launch("sph.hold_outlets", hold_, n, wg_);
}

void OutletZones::remove_past(ParticleStore& ps) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0 || zones_count_ == 0) return;
    cl_rt::set_args(remove_, ps.ranges.first_owned(), ps.ranges.end_owned(), grid_.params(), zones_count_, zones_, ps.pos, ps.id);
    device_.launch("sph.remove_past_outlets", remove_, n, wg_);
}

}  // namespace clsph::device
