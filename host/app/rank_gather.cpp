#include "rank_gather.hpp"

#include <clsph/error.hpp>

#include <cstring>
#include <string>

namespace clsph::app {
namespace {

// Per particle: id 4, type 1, position 24, velocity 12, density 4, pressure 4.
constexpr std::size_t kBytes = 49;

std::string pack(const Particles& p) {
    std::string out(kBytes * p.size(), '\0');
    char* at = out.data();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto type = static_cast<std::uint8_t>(p.type[i]);
        std::memcpy(at, &p.id[i], 4);
        std::memcpy(at + 4, &type, 1);
        std::memcpy(at + 5, p.position[i].data(), 24);
        std::memcpy(at + 29, p.velocity[i].data(), 12);
        std::memcpy(at + 41, &p.density[i], 4);
        std::memcpy(at + 45, &p.pressure[i], 4);
        at += kBytes;
    }
    return out;
}

void unpack(const std::string& bytes, Particles& into) {
    if (bytes.size() % kBytes != 0) throw Error("gathering particles from the ranks: a rank's part is malformed");
    for (const char* at = bytes.data(); at < bytes.data() + bytes.size(); at += kBytes) {
        std::uint32_t id = 0;
        std::uint8_t type = 0;
        std::array<double, 3> x{};
        std::array<float, 3> v{};
        float rho = 0, pressure = 0;
        std::memcpy(&id, at, 4);
        std::memcpy(&type, at + 4, 1);
        std::memcpy(x.data(), at + 5, 24);
        std::memcpy(v.data(), at + 29, 12);
        std::memcpy(&rho, at + 41, 4);
        std::memcpy(&pressure, at + 45, 4);
        into.push_back(id, static_cast<ParticleType>(type), x, v, rho, pressure);
    }
}

}  // namespace

Particles gather_particles_to_rank0(Ranks& ranks, const Particles& mine) {
    Particles all;
    for (const auto& part : gather_text_to(ranks, pack(mine), 0)) unpack(part, all);
    return all;
}

}  // namespace clsph::app
