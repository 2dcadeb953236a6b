// The four arrays that make a particle on a device, structure of arrays:
//   pos     float4  offset from the cell centre (xyz) + cell key bits (w)   — see grid.hpp
//   velrho  float4  velocity (xyz) + density (w)
//   accel   float4  acceleration (xyz) + drho/dt (w) of the last force pass (the second kick needs it)
//   id      uint    id (low 31 bits) + type (top bit)
// The particle store, the exchange's outbox and inbox hold particles as ParticleArrays; a block
// staged in host memory holds m of them as [pos m | velrho m | accel m | id m].
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "device/sizing.hpp"

#include <cstddef>
#include <string>

namespace clsph::device {

struct ParticleArrays {
    cl_rt::Buffer pos, velrho, accel, id;

    static constexpr std::size_t kFloat4 = 4 * sizeof(float);
    static constexpr std::size_t kBytesPerParticle = sizing::kParticleBytes;

    // f(buffer, bytes per element, name) for each array, in the staged block's order.
    template <class F>
    void each(F&& f) {
        f(pos, kFloat4, "positions");
        f(velrho, kFloat4, "velocity+density");
        f(accel, kFloat4, "acceleration+drho/dt");
        f(id, sizeof(std::uint32_t), "ids");
    }
    template <class F>
    void each(F&& f) const {
        const_cast<ParticleArrays*>(this)->each([&](cl_rt::Buffer& b, std::size_t e, const char* n) { f(b, e, n); });
    }
    // Room for `capacity` particles, nothing kept (the old arrays are freed first).
    void allocate(cl_rt::Device& device, std::size_t capacity, const std::string& what);
    // Room for `capacity` particles keeping the first `keep` (one array at a time: the peak is the
    // old arrays plus one new one).
    void grow(cl_rt::Device& device, std::size_t capacity, std::size_t keep, const std::string& what);
    std::size_t capacity() const { return id.bytes() / sizeof(std::uint32_t); }
};

// Particles [from, from + n) of `src` to [to, to + n) of `dst`, on the device's compute queue.
void copy_particles(cl_rt::Device& device, const ParticleArrays& src, std::size_t from, ParticleArrays& dst,
                    std::size_t to, std::size_t n);
// Non-blocking: particles [from, from + n) of `src` into a host block of n (see above), and back.
void read_particles(cl_rt::Device& device, const ParticleArrays& src, std::size_t from, std::size_t n,
                    unsigned char* block, cl_rt::EventSet& done, cl_rt::Device::On on);
void write_particles(cl_rt::Device& device, ParticleArrays& dst, std::size_t to, std::size_t n,
                     const unsigned char* block, cl_rt::EventSet& done, cl_rt::Device::On on);

}  // namespace clsph::device
