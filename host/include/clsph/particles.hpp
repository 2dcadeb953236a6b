// Particles as a host program sees them: a structure of arrays, positions in double.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace clsph {

enum class ParticleType : std::uint8_t { fluid = 0, boundary = 1 };

struct Particles {
    std::vector<std::uint32_t> id;                 // unique per particle, stable over a run
    std::vector<ParticleType> type;
    std::vector<std::array<double, 3>> position;   // m
    std::vector<std::array<float, 3>> velocity;    // m/s
    std::vector<float> density;                    // kg/m^3
    std::vector<float> pressure;                   // Pa

    std::size_t size() const { return id.size(); }
    void resize(std::size_t n) {
        id.resize(n);
        type.resize(n, ParticleType::fluid);
        position.resize(n);
        velocity.resize(n);
        density.resize(n);
        pressure.resize(n);
    }
    void push_back(std::uint32_t i, ParticleType t, std::array<double, 3> x, std::array<float, 3> v, float rho,
                   float p) {
        id.push_back(i);
        type.push_back(t);
        position.push_back(x);
        velocity.push_back(v);
        density.push_back(rho);
        pressure.push_back(p);
    }
};

}  // namespace clsph
