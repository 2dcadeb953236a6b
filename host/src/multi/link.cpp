#include "multi/link.hpp"

#include <cstring>

namespace clsph::multi {

void ParticleBatch::append(const ParticleBatch& o, std::size_t first, std::size_t count) {
    pos.insert(pos.end(), o.pos.begin() + 4 * first, o.pos.begin() + 4 * (first + count));
    velrho.insert(velrho.end(), o.velrho.begin() + 4 * first, o.velrho.begin() + 4 * (first + count));
    accel.insert(accel.end(), o.accel.begin() + 4 * first, o.accel.begin() + 4 * (first + count));
    id.insert(id.end(), o.id.begin() + first, o.id.begin() + first + count);
}

std::uint32_t ParticleBatch::key(std::size_t i) const {
    std::uint32_t k;
    std::memcpy(&k, &pos[4 * i + 3], sizeof k);
    return k;
}

void read_range(device::ParticleStore& ps, std::size_t first, std::size_t count, ParticleBatch& out) {
    out.pos.resize(4 * count);
    out.velrho.resize(4 * count);
    out.accel.resize(4 * count);
    out.id.resize(count);
    auto& d = ps.device();
    d.read(ps.pos, out.pos.data(), 4 * count, 4 * first);
    d.read(ps.velrho, out.velrho.data(), 4 * count, 4 * first);
    d.read(ps.accel, out.accel.data(), 4 * count, 4 * first);
    d.read(ps.id, out.id.data(), count, first);
}

void write_range(device::ParticleStore& ps, std::size_t at, const ParticleBatch& b) {
    auto& d = ps.device();
    d.write(ps.pos, b.pos.data(), b.pos.size(), 4 * at);
    d.write(ps.velrho, b.velrho.data(), b.velrho.size(), 4 * at);
    d.write(ps.accel, b.accel.data(), b.accel.size(), 4 * at);
    d.write(ps.id, b.id.data(), b.id.size(), at);
}

}  // namespace clsph::multi
