#include "device/primitives_launch.hpp"

#include "cl/errors.hpp"
#include "clsph/error.hpp"

#include <limits>

namespace clsph::device {

cl_uint as_uint(std::size_t n) {
    // Kernels compute tile ends as base + TILE in uint: keep a margin below 2^32.
    constexpr std::size_t limit = std::numeric_limits<cl_uint>::max() - (std::size_t{1} << 17);
    if (n > limit)
        throw Error("primitives: " + std::to_string(n) + " elements is more than the " + std::to_string(limit) +
                    " a device primitive can index with 32-bit integers");
    return static_cast<cl_uint>(n);
}

void require_elements(const std::string& what, const cl_rt::Buffer& buffer, std::size_t elements) {
    if (buffer.bytes() < elements * sizeof(cl_uint))
        throw Error(what + " buffer holds " + std::to_string(buffer.bytes() / sizeof(cl_uint)) +
                    " uints but needs " + std::to_string(elements));
}

void ensure_capacity(cl_rt::Device& dev, cl_rt::Buffer& buffer, std::size_t bytes, const std::string& what) {
    if (buffer.bytes() >= bytes && buffer) return;
    buffer = cl_rt::Buffer();  // free the old one first: its bytes count against the device
    buffer = dev.alloc(bytes, what);
}

std::size_t resolve_work_group(cl_rt::Device& dev, std::size_t requested, std::size_t cap,
                               const std::function<std::vector<cl::Kernel*>(std::size_t)>& build) {
    std::size_t wg = requested ? requested : dev.work_group_size(cap);
    if (wg == 0 || (wg & (wg - 1)) != 0)
        throw Error("primitives: work-group size " + std::to_string(wg) + " is not a power of two");
    if (wg > dev.info().max_work_group_size)
        throw Error("primitives: work-group size " + std::to_string(wg) + " exceeds the " +
                    std::to_string(dev.info().max_work_group_size) + " of " + dev.label());
    for (;;) {
        std::size_t accepted = wg;
        const auto kernels = build(wg);
        if (dev.quirks().kernel_work_group_size_understated) return wg;  // see quirks.hpp
        for (cl::Kernel* k : kernels) {
            const auto limit = cl_rt::guarded("querying a kernel's work-group size", dev.label(), [&] {
                return k->getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev.cl_device());
            });
            accepted = std::min(accepted, limit);
        }
        if (accepted >= wg) return wg;
        if (requested) {
            throw Error("primitives: a kernel accepts at most " + std::to_string(accepted) +
                        " work-items per group on " + dev.label() + ", not the " + std::to_string(wg) + " asked for");
        }
        while (wg > accepted) wg /= 2;
        if (wg < 16) throw Error("primitives: " + dev.label() + " runs these kernels only in tiny work-groups");
    }
}

}  // namespace clsph::device
