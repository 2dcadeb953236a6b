#include "device/particle_arrays.hpp"

namespace clsph::device {

void ParticleArrays::allocate(cl_rt::Device& device, std::size_t capacity, const std::string& what) {
    each([&](cl_rt::Buffer& b, std::size_t, const char*) { b = cl_rt::Buffer(); });
    each([&](cl_rt::Buffer& b, std::size_t elem, const char* name) { b = device.alloc(capacity * elem, what + ": " + name); });
}

void ParticleArrays::grow(cl_rt::Device& device, std::size_t capacity, std::size_t keep, const std::string& what) {
    each([&](cl_rt::Buffer& b, std::size_t elem, const char* name) {
        cl_rt::Buffer nb = device.alloc(capacity * elem, what + ": " + name);
        device.copy(b, nb, keep * elem);
        b = std::move(nb);
    });
}

void copy_particles(cl_rt::Device& device, const ParticleArrays& src, std::size_t from, ParticleArrays& dst,
                    std::size_t to, std::size_t n) {
    if (n == 0) return;
    const cl_rt::Buffer* s[] = {&src.pos, &src.velrho, &src.accel, &src.id};
    int k = 0;
    dst.each([&](cl_rt::Buffer& d, std::size_t elem, const char*) {
        device.copy(*s[k++], d, n * elem, from * elem, to * elem);
    });
}

void read_particles(cl_rt::Device& device, const ParticleArrays& src, std::size_t from, std::size_t n,
                    unsigned char* block, cl_rt::EventSet& done, cl_rt::Device::On on) {
    if (n == 0) return;
    src.each([&](const cl_rt::Buffer& b, std::size_t elem, const char*) {
        device.read_async(b, block, n * elem, from * elem, done, on);
        block += n * elem;
    });
}

void write_particles(cl_rt::Device& device, ParticleArrays& dst, std::size_t to, std::size_t n,
                     const unsigned char* block, cl_rt::EventSet& done, cl_rt::Device::On on) {
    if (n == 0) return;
    dst.each([&](cl_rt::Buffer& b, std::size_t elem, const char*) {
        device.write_async(b, block, n * elem, to * elem, done, on);
        block += n * elem;
    });
}

}  // namespace clsph::device
