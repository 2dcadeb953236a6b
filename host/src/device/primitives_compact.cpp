// Compact: exclusive scan of (flags != 0) into offsets, then every kept element moves to its
// offset (kernels/compact.cl). The count is the scan's total: one blocking read of one uint.
#include "device/primitives.hpp"

#include "device/primitives_launch.hpp"

namespace clsph::device {

struct Compact::Impl {
    cl_rt::Device& dev;
    Scan scan;
    cl::Kernel scatter;
    std::size_t wg;
    cl_rt::Buffer offsets;

    explicit Impl(cl_rt::Device& device)
        : dev(device), scan(device, Scan::Config{0, 0, "compact.scan"}), wg(device.work_group_size(256)) {
        scatter = dev.kernel("compact.cl", "compact_scatter");
    }

    std::size_t compact(const cl_rt::Buffer& flags, const cl_rt::Buffer& values, cl_rt::Buffer& out, std::size_t n) {
        require_elements("compaction flags", flags, n);
        require_elements("compaction values", values, n);
        require_elements("compaction output", out, n);
        if (n == 0) return 0;
        ensure_capacity(dev, offsets, (n + 1) * sizeof(cl_uint), "compaction offsets");
        scan.exclusive_flags(flags, offsets, n);
        set_args(scatter, flags.get(), values.get(), offsets.get(), out.get(), as_uint(n));
        dev.launch("compact.scatter", scatter, n, wg);
        cl_uint count = 0;
        dev.read(offsets, &count, 1, n);  // in-order queue: waits for the scatter too
        return count;
    }
};

Compact::Compact(cl_rt::Device& device) : impl_(std::make_shared<Impl>(device)) {}

std::size_t Compact::compact(const cl_rt::Buffer& flags, const cl_rt::Buffer& values, cl_rt::Buffer& out,
                             std::size_t n) {
    return impl_->compact(flags, values, out, n);
}

}  // namespace clsph::device
