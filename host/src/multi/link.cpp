#include "multi/link.hpp"

#include "clsph/error.hpp"

#include <string>

namespace clsph::multi {

void StagedLink::prefetch(const device::ParticleArrays& src, std::size_t first, std::size_t window,
                          const cl_rt::EventSet& after, cl_rt::EventSet& fetched) {
    window_ = window;
    if (window == 0) return;
    staging_.reserve(from_, window * device::ParticleArrays::kBytesPerParticle);
    unsigned char* block = staging_.data();
    src.each([&](const cl_rt::Buffer& b, std::size_t elem, const char*) {
        from_.read_async(b, block, window * elem, first * elem, fetched, cl_rt::Device::On::transfer, &after);
        block += window * elem;
    });
}

void StagedLink::send(const device::ParticleArrays& src, std::size_t first, std::size_t n, cl_rt::EventSet& sent) {
    n_ = n;
    if (window_ > 0) {  // on its way already: the block is the window's first n
        if (n > window_)
            throw Error("link: a block of " + std::to_string(n) + " particles from a window of " + std::to_string(window_));
        stride_ = window_;
        window_ = 0;
        return;
    }
    stride_ = n;
    if (n == 0) return;
    staging_.reserve(from_, n * device::ParticleArrays::kBytesPerParticle);
    device::read_particles(from_, src, first, n, staging_.data(), sent, cl_rt::Device::On::transfer);
}

void StagedLink::receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) {
    if (n_ == 0) return;
    const unsigned char* block = staging_.data();
    dst.each([&](cl_rt::Buffer& b, std::size_t elem, const char*) {
        to_.write_async(b, block, n_ * elem, to * elem, received, cl_rt::Device::On::transfer);
        block += stride_ * elem;
    });
}

}  // namespace clsph::multi
