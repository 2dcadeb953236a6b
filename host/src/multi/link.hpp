// Moving particles between devices. Every transfer here is staged through host memory, which
// works between any two devices of any vendors and contexts (the foundation's transfer benchmark
// found shared-context copies between two NVIDIA GPUs stall ~200 ms, and staging is what works
// across vendors). A batch holds the four particle arrays of a contiguous range.
#pragma once
#include "device/particle_store.hpp"

#include <cstdint>
#include <vector>

namespace clsph::multi {

struct ParticleBatch {
    std::vector<float> pos, velrho, accel;  // 4 floats per particle
    std::vector<std::uint32_t> id;
    std::size_t size() const { return id.size(); }
    void append(const ParticleBatch& o, std::size_t first, std::size_t count);
    std::uint32_t key(std::size_t i) const;  // the cell key kept in pos.w
};

// Reads particles [first, first + count) of a store (blocking).
void read_range(device::ParticleStore& ps, std::size_t first, std::size_t count, ParticleBatch& out);
// Writes a batch at position `at` of a store (blocking; the store must have the capacity).
void write_range(device::ParticleStore& ps, std::size_t at, const ParticleBatch& b);

}  // namespace clsph::multi
