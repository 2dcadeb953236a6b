// The particles of one device in device memory: the four particle arrays (particle_arrays.hpp)
// plus what sorting them needs:
//   keys, vals      sort keys and sort values / cell index per particle (capacity + 1 for the scan)
//   scratch float4  the one rotating buffer through which arrays are reordered
// Active particles occupy [0, active) in sorted order: ghosts of the device before, the owned
// particles, ghosts of the device after — [ghosts | owned | ghosts], so one sort orders all of them
// and the capacity beyond `active` is the reserve that arrivals and ghosts land in.
#pragma once
#include "cl/device.hpp"
#include "clsph/particles.hpp"
#include "device/grid.hpp"
#include "device/particle_arrays.hpp"

#include <cstddef>

namespace clsph::device {

struct ParticleRanges {
    std::size_t ghosts_before = 0, owned = 0, ghosts_after = 0;
    std::size_t active() const { return ghosts_before + owned + ghosts_after; }
    std::size_t first_owned() const { return ghosts_before; }
    std::size_t end_owned() const { return ghosts_before + owned; }
};

class ParticleStore : public ParticleArrays {
public:
    // headroom: extra capacity fraction kept when growing (so buffers do not grow every step).
    ParticleStore(cl_rt::Device& device, const Grid& grid, std::size_t capacity, double headroom = 0.25);

    // Replaces the device's particles with `p` (all owned). Particles outside the domain are kept
    // with an invalid key; the next cell pass removes and counts them.
    void upload(const Particles& p);
    // Host copy of the owned particles, in their current (sorted) order; pressure is left at 0
    // (it is the physics' equation of state that knows it).
    Particles download();

    // Grows every array (keeping contents) so `n` particles fit; returns true if it reallocated.
    bool reserve(std::size_t n);

    cl_rt::Device& device() { return device_; }
    const Grid& grid() const { return grid_; }
    std::size_t capacity() const { return capacity_; }
    ParticleRanges ranges;

    cl_rt::Buffer keys, vals, scratch;

private:
    void allocate(std::size_t capacity);
    cl_rt::Device& device_;
    const Grid& grid_;
    double headroom_;
    std::size_t capacity_ = 0;
};

// Host particles from the device's words, n of each: pos (offset from the cell centre xyz, key
// bits w), velrho, id words; pressure left at 0.
Particles decode_particles(const Grid& grid, const float* pos, const float* velrho, const std::uint32_t* ids, std::size_t n);

}  // namespace clsph::device
