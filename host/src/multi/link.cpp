#include "multi/link.hpp"

namespace clsph::multi {

void StagedLink::send(const device::ParticleArrays& src, std::size_t first, std::size_t n, cl_rt::EventSet& sent) {
    n_ = n;
    if (n == 0) return;
    staging_.reserve(from_, n * device::ParticleArrays::kBytesPerParticle);
    device::read_particles(from_, src, first, n, staging_.data(), sent, cl_rt::Device::On::transfer);
}

void StagedLink::receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) {
    if (n_ == 0) return;
    device::write_particles(to_, dst, to, n_, staging_.data(), received, cl_rt::Device::On::transfer);
}

}  // namespace clsph::multi
