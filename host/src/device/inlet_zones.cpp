#include "device/inlet_zones.hpp"

#include "cl/kernel_args.hpp"
#include "scene/open_boundaries.hpp"
#include "shared.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace clsph::device {

InletZones::InletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene)
    : device_(device), grid_(grid), inlets_(scene.inlets.size()), wg_(device.work_group_size(64)) {
    const double dp = scene.physics.dp;
    std::vector<InletBox> boxes;
    std::vector<float> factors;
    for (const Inlet& in : scene.inlets) {
        InletBox b{};
        double speed = 0;
        for (int k = 0; k < 3; ++k) speed = std::max(speed, std::fabs(in.velocity[k]));
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = static_cast<float>(in.min[k] - scene.domain.min[k]);
            b.hi[k] = static_cast<float>(in.max[k] - scene.domain.min[k]);
            b.direction[k] = static_cast<float>(in.velocity[k] == 0.0 ? 0.0 : in.velocity[k] / speed);
        }
        const scene::InletColumns c = scene::inlet_columns(in, dp);
        b.axis = c.axis < 0 ? 3u : static_cast<cl_uint>(c.axis);
        b.column0 = c.axis < 0 ? 0.0f : static_cast<float>(c.first - scene.domain.min[static_cast<std::size_t>(c.axis)]);
        b.inv_dp = static_cast<float>(1.0 / dp);
        b.columns = static_cast<cl_uint>(c.factor.size());
        b.first = static_cast<cl_uint>(factors.size());
        for (double f : c.factor) factors.push_back(static_cast<float>(f));
        boxes.push_back(b);
    }
    if (boxes.empty()) boxes.push_back(InletBox{});
    if (factors.empty()) factors.push_back(1.0f);
    boxes_ = device_.alloc(boxes.size() * sizeof(InletBox), "inlet boxes");
    device_.write(boxes_, boxes.data(), boxes.size());
    factors_ = device_.alloc(factors.size() * sizeof(float), "inlet profiles");
    device_.write(factors_, factors.data(), factors.size());
    speeds_ = device_.alloc(boxes.size() * sizeof(float), "inlet speeds");
    speeds_written_.assign(inlets_, std::numeric_limits<float>::quiet_NaN());
    kernel_ = device_.kernel("inlets.cl", "impose_inlets", grid_.kernel_options());
}

std::vector<std::pair<const char*, std::size_t>> InletZones::buffers(const Scene& scene) {
    if (scene.inlets.empty()) return {};
    std::size_t factors = 0;
    for (const Inlet& in : scene.inlets) factors += scene::inlet_columns(in, scene.physics.dp).factor.size();
    const std::size_t n = scene.inlets.size();
    return {{"inlet boxes", n * sizeof(InletBox)}, {"inlet profiles", factors * sizeof(float)}, {"inlet speeds", n * sizeof(float)}};
}

void InletZones::impose(ParticleStore& ps, const std::vector<double>& speeds, bool after_forces) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0 || inlets_ == 0) return;
    for (std::size_t k = 0; k < inlets_; ++k) {
        const float u = static_cast<float>(speeds.at(k));
        if (u == speeds_written_[k]) continue;  // a constant speed is written once
        device_.fill(speeds_, u, 1, k);        // the pattern is copied at once: nothing to keep
        speeds_written_[k] = u;
    }
    cl_rt::Buffer& accel_new = after_forces ? ps.scratch : ps.accel;
    cl_uint i = 0;
    kernel_.setArg(i++, cl_rt::checked_uint(ps.ranges.first_owned()));
    kernel_.setArg(i++, cl_rt::checked_uint(ps.ranges.end_owned()));
    kernel_.setArg(i++, grid_.params());
    kernel_.setArg(i++, cl_rt::checked_uint(inlets_));
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{&boxes_, &factors_, &speeds_, &ps.pos, &ps.id,
                                                                             &ps.velrho, &ps.accel, &accel_new})
        kernel_.setArg(i++, b->get());
    device_.launch(after_forces ? "sph.impose_inlets" : "sph.impose_inlets_drift", kernel_, n, wg_);
}

void InletZones::write(ParticleArrays& dst, std::size_t at, const Particles& p, const std::vector<std::size_t>& which) {
    const std::size_t n = which.size();
    if (n == 0) return;
    std::vector<float> hp(4 * n), hv(4 * n), ha(4 * n, 0.0f);
    std::vector<std::uint32_t> hid(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t j = which[k];
        std::array<float, 3> off{};
        const std::uint32_t key = grid_.locate(p.position[j], off);
        std::memcpy(&hp[4 * k], off.data(), sizeof off);
        std::memcpy(&hp[4 * k + 3], &key, sizeof key);
        for (int c = 0; c < 3; ++c) hv[4 * k + static_cast<std::size_t>(c)] = p.velocity[j][static_cast<std::size_t>(c)];
        hv[4 * k + 3] = p.density[j];
        hid[k] = p.id[j] | (static_cast<std::uint32_t>(p.type[j]) << CLSPH_TYPE_SHIFT);
    }
    device_.write(dst.pos, hp.data(), 4 * n, 4 * at);
    device_.write(dst.velrho, hv.data(), 4 * n, 4 * at);
    device_.write(dst.accel, ha.data(), 4 * n, 4 * at);
    device_.write(dst.id, hid.data(), n, at);
}

}  // namespace clsph::device
