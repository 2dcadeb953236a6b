#include "device/particle_store.hpp"
#include "device/sizing.hpp"

#include "clsph/error.hpp"

#include <cstring>
#include <vector>

namespace clsph::device {

ParticleStore::ParticleStore(cl_rt::Device& device, const Grid& grid, std::size_t capacity, double headroom)
    : device_(device), grid_(grid), headroom_(headroom) {
    allocate(std::max<std::size_t>(capacity, 1));
}

void ParticleStore::allocate(std::size_t cap) {
    auto& d = device_;
    const std::size_t f4 = sizeof(float) * 4, u = sizeof(std::uint32_t);
    ParticleArrays::allocate(d, cap, "particles");
    keys = d.alloc((cap + 1) * u, "sort keys");
    vals = d.alloc((cap + 1) * u, "sort values / cell index");
    scratch = d.alloc(cap * f4, "reorder scratch");
    capacity_ = cap;
}

bool ParticleStore::reserve(std::size_t n) {
    if (n <= capacity_) return false;
    const std::size_t cap = sizing::grown_capacity(n, headroom_);
    const std::size_t keep = ranges.active();
    if (keep == 0) {
        // Nothing to keep (the first upload, the generation on the device): the old arrays go
        // before the new ones are made, so the peak is the new arrays alone, not old + new.
        keys = cl_rt::Buffer();
        vals = cl_rt::Buffer();
        scratch = cl_rt::Buffer();
        allocate(cap);  // ParticleArrays::allocate frees its arrays first
        return true;
    }
    // Grow one array at a time through the device, so the peak is old + one new array.
    ParticleArrays::grow(device_, cap, keep, "particles");
    // Keys and values too: a sort of the active particles may already be in them (several devices).
    const std::size_t f4 = sizeof(float) * 4, u = sizeof(std::uint32_t);
    auto grow = [&](cl_rt::Buffer& b, std::size_t elem, std::size_t count, const char* what) {
        cl_rt::Buffer nb = device_.alloc(count * elem, what);
        device_.copy(b, nb, keep * elem);
        b = std::move(nb);
    };
    grow(keys, u, cap + 1, "sort keys");
    grow(vals, u, cap + 1, "sort values / cell index");
    scratch = cl_rt::Buffer();
    scratch = device_.alloc(cap * f4, "reorder scratch");
    capacity_ = cap;
    return true;
}

void ParticleStore::upload(const Particles& p) {
    const std::size_t n = p.size();
    reserve(n);
    std::vector<float> hp(4 * n), hv(4 * n);
    std::vector<std::uint32_t> hid(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::array<float, 3> off{};
        const std::uint32_t key = grid_.locate(p.position[i], off);
        std::memcpy(&hp[4 * i], off.data(), sizeof off);
        std::memcpy(&hp[4 * i + 3], &key, sizeof key);
        for (int k = 0; k < 3; ++k) hv[4 * i + k] = p.velocity[i][k];
        hv[4 * i + 3] = p.density[i];
        if (p.id[i] > CLSPH_ID_MASK) throw Error("particle id " + std::to_string(p.id[i]) + " is above the 2^31 - 1 limit");
        hid[i] = p.id[i] | (static_cast<std::uint32_t>(p.type[i]) << CLSPH_TYPE_SHIFT);
    }
    device_.write(pos, hp.data(), 4 * n);
    device_.write(velrho, hv.data(), 4 * n);
    device_.write(id, hid.data(), n);
    device_.fill(accel, 0.0f, 4 * std::max<std::size_t>(n, 1));
    ranges = ParticleRanges{0, n, 0};
}

Particles ParticleStore::download() {
    const std::size_t first = ranges.first_owned(), n = ranges.owned;
    std::vector<float> hp(4 * n), hv(4 * n);
    std::vector<std::uint32_t> hid(n);
    device_.read(pos, hp.data(), 4 * n, 4 * first);
    device_.read(velrho, hv.data(), 4 * n, 4 * first);
    device_.read(id, hid.data(), n, first);
    return decode_particles(grid_, hp.data(), hv.data(), hid.data(), n);
}

Particles decode_particles(const Grid& grid, const float* pos, const float* velrho, const std::uint32_t* ids, std::size_t n) {
    Particles p;
    p.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t key;
        std::memcpy(&key, &pos[4 * i + 3], sizeof key);
        p.position[i] = grid.position(key, {pos[4 * i], pos[4 * i + 1], pos[4 * i + 2]});
        p.velocity[i] = {velrho[4 * i], velrho[4 * i + 1], velrho[4 * i + 2]};
        p.density[i] = velrho[4 * i + 3];
        p.pressure[i] = 0.0f;
        p.id[i] = ids[i] & CLSPH_ID_MASK;
        p.type[i] = static_cast<ParticleType>(ids[i] >> CLSPH_TYPE_SHIFT);
    }
    return p;
}

}  // namespace clsph::device
