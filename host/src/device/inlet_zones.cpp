#include "device/inlet_zones.hpp"

#include "cl/kernel_args.hpp"

#include <cstring>

namespace clsph::device {

InletZones::InletZones(cl_rt::Device& device, const Grid& grid, const Scene& scene)
    : device_(device), grid_(grid), inlets_(scene.inlets.size()), wg_(device.work_group_size(64)) {
    std::vector<float> boxes;
    for (const Inlet& in : scene.inlets) {
        for (int k = 0; k < 3; ++k) boxes.push_back(static_cast<float>(in.min[k] - scene.domain.min[k]));
        for (int k = 0; k < 3; ++k) boxes.push_back(static_cast<float>(in.max[k] - scene.domain.min[k]));
        for (int k = 0; k < 3; ++k) boxes.push_back(static_cast<float>(in.velocity[k]));
    }
    if (boxes.empty()) boxes.assign(9, 0.0f);
    boxes_ = device_.alloc(boxes.size() * sizeof(float), "inlet boxes");
    device_.write(boxes_, boxes.data(), boxes.size());
    kernel_ = device_.kernel("inlets.cl", "impose_inlets", grid_.kernel_options());
}

void InletZones::impose(ParticleStore& ps) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0 || inlets_ == 0) return;
    cl_uint i = 0;
    kernel_.setArg(i++, cl_rt::checked_uint(ps.ranges.first_owned()));
    kernel_.setArg(i++, cl_rt::checked_uint(ps.ranges.end_owned()));
    kernel_.setArg(i++, grid_.params());
    kernel_.setArg(i++, cl_rt::checked_uint(inlets_));
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{&boxes_, &ps.pos, &ps.id, &ps.velrho, &ps.accel})
        kernel_.setArg(i++, b->get());
    device_.launch("sph.impose_inlets", kernel_, n, wg_);
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
