// What the driver reads from its slabs between steps: the particle count, the particles (all, or
// thinned on the device) and the probes, each sampled on the slab that owns its column.
#include "multi/slab_driver.hpp"

#include "device/thin_download.hpp"

namespace clsph::multi {

std::size_t SlabDriver::owned() const {
    // Across ranks: every slab's, as gathered after the last step (no collective here).
    std::size_t n = 0;
    for (std::size_t d = 0; d < slabs_.size(); ++d) n += here(d) ? slabs_[d].store->ranges.owned : figures_[d].owned;
    return n;
}

Particles SlabDriver::download() {
    Particles all;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (!here(d)) continue;  // across ranks: this rank's particles
        const Particles p = slabs_[d].store->download();
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    }
    return all;
}

Particles SlabDriver::download_every(std::size_t d, std::uint32_t stride, const std::optional<std::array<double, 6>>& box) {
    return device::ThinDownload(*slabs_[d].device, partition_.grid()).download(*slabs_[d].store, stride, box);
}

std::vector<std::array<float, 2>> SlabDriver::probe(const std::vector<std::array<double, 3>>& points) {
    std::vector<std::array<float, 2>> out(points.size(), {0.0f, 0.0f});
    // Each point is evaluated on the device owning its column (which holds the ghosts it needs).
    std::vector<std::vector<std::size_t>> which(slabs_.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::array<float, 3> off{};
        const auto key = partition_.grid().locate(points[i], off);
        if (key == partition_.grid().params().invalid_key) continue;
        which[partition_.owner_of(key, slabs_)].push_back(i);
    }
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (which[d].empty() || !here(d)) continue;
        std::vector<std::array<double, 3>> pts;
        for (auto i : which[d]) pts.push_back(points[i]);
        const auto r = slabs_[d].physics->probe(*slabs_[d].store, *slabs_[d].cells, pts);
        for (std::size_t k = 0; k < pts.size(); ++k) out[which[d][k]] = r[k];
    }
    if (across_ranks()) {  // each point was evaluated on one rank: the others' are zeros
        std::vector<double> v(2 * out.size());
        for (std::size_t i = 0; i < out.size(); ++i) v[2 * i] = out[i][0], v[2 * i + 1] = out[i][1];
        ranks_.ranks->sum(v);
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = {static_cast<float>(v[2 * i]), static_cast<float>(v[2 * i + 1])};
    }
    return out;
}

}  // namespace clsph::multi
