// A run's particles by id as raw bytes (position in double as downloaded, velocity, density), for
// the suites that check two runs are bitwise the same (step ahead, moving solids, floating bodies,
// the cluster form).
#pragma once
#include "clsph/particles.hpp"
#include "clsph/simulation.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <vector>

namespace clsph::test {

using ParticleBytes = std::array<unsigned char, 3 * sizeof(double) + 4 * sizeof(float)>;
using State = std::map<std::uint32_t, ParticleBytes>;

inline State state_of(const Particles& p) {
    State s;
    for (std::size_t i = 0; i < p.size(); ++i) {
        auto& b = s[p.id[i]];
        std::memcpy(b.data(), p.position[i].data(), 3 * sizeof(double));
        const float v[4] = {p.velocity[i][0], p.velocity[i][1], p.velocity[i][2], p.density[i]};
        std::memcpy(b.data() + 3 * sizeof(double), v, sizeof v);
    }
    return s;
}

inline State state_of(Simulation& sim) { return state_of(sim.particles()); }

// How many particles differ in any bit, or -1 when the two hold different ids.
inline long differing(const State& a, const State& b) {
    if (a.size() != b.size()) return -1;
    long n = 0;
    for (const auto& [id, bytes] : a) {
        const auto it = b.find(id);
        if (it == b.end()) return -1;
        n += it->second != bytes;
    }
    return n;
}

// Every body of two runs the same, to the bit: pose, velocities, force and torque.
inline bool same_bodies(const std::vector<BodySample>& a, const std::vector<BodySample>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].position != b[i].position || a[i].quaternion != b[i].quaternion || a[i].velocity != b[i].velocity ||
            a[i].angular_velocity != b[i].angular_velocity || a[i].force != b[i].force || a[i].torque != b[i].torque)
            return false;
    return true;
}

}  // namespace clsph::test
