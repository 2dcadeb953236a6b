#include "device/thin_download.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

namespace clsph::device {

ThinDownload::ThinDownload(cl_rt::Device& device, const Grid& grid)
    : device_(device), grid_(grid), scan_(device), wg_(device.work_group_size(256)) {
    flags_k_ = device.kernel("select.cl", "stride_flags");
    gather_k_ = device.kernel("select.cl", "stride_gather");
}

Particles ThinDownload::download(ParticleStore& store, std::uint32_t stride, const std::optional<std::array<double, 6>>& box) {
    auto& d = device_;
    if (stride == 0) throw Error("a thinned download needs a stride of at least 1");
    const std::size_t first = store.ranges.first_owned(), n = store.ranges.owned;
    Particles p;
    if (n == 0) return p;
    // The cells the box meets, per key position (all cells without a box, and along a periodic axis).
    const auto& g = grid_.params();
    const std::uint32_t count[3] = {g.n_s, g.n_a, g.n_b};
    cl_uint4 lo = {{0, 0, 0, 0}}, hi = {{count[0] - 1, count[1] - 1, count[2] - 1, 0}};
    if (box) {
        for (int kp = 0; kp < 3; ++kp) {
            const int axis = grid_.axis(kp);
            if (grid_.periodic()[axis]) continue;
            auto cell_of = [&](double x) {
                std::uint32_t c = 0;
                float off = 0.0f;
                if (grid_.locate_axis(kp, x, c, off)) return static_cast<long long>(c);
                return x < grid_.domain().lo[axis] ? -1LL : static_cast<long long>(count[kp]);
            };
            const long long a = cell_of((*box)[axis]), b = cell_of((*box)[axis + 3]);
            if (b < 0 || a >= static_cast<long long>(count[kp]) || a > b) return p;  // the box misses the domain
            // A cell more either side: a particle at a cell's face may round into its neighbour.
            lo.s[kp] = static_cast<cl_uint>(std::max(a - 1, 0LL));
            hi.s[kp] = static_cast<cl_uint>(std::min(b + 1, static_cast<long long>(count[kp]) - 1));
        }
    }
    // Flags, scanned in place, in the reorder scratch (4 uints per particle of capacity).
    cl_rt::set_args(flags_k_, n, first, cl_uint{stride}, lo, hi, g.shift_s, g.shift_a, g.mask_a, g.mask_b,
                    static_cast<cl_uint>(grid_.reach()), g.invalid_key, store.id, store.pos, store.scratch);
    d.launch("download.flags", flags_k_, n, wg_);
    scan_.exclusive(store.scratch, store.scratch, n);
    cl_uint m = 0;
    d.read(store.scratch, &m, 1, n);
    if (m == 0) return p;
    const std::size_t f4 = 4 * sizeof(float);
    cl_rt::Buffer out_pos = d.alloc(m * f4, "thinned frame"), out_vr = d.alloc(m * f4, "thinned frame"),
                  out_id = d.alloc(m * sizeof(std::uint32_t), "thinned frame");
    cl_rt::set_args(gather_k_, n, first, store.id, store.scratch, store.pos, store.velrho, out_pos, out_vr, out_id);
    d.launch("download.gather", gather_k_, n, wg_);
    std::vector<float> hp(4 * std::size_t{m}), hv(4 * std::size_t{m});
    std::vector<std::uint32_t> hid(m);
    d.read(out_pos, hp.data(), hp.size());
    d.read(out_vr, hv.data(), hv.size());
    d.read(out_id, hid.data(), hid.size());
    p = decode_particles(grid_, hp.data(), hv.data(), hid.data(), m);
    if (box) {  // the cells' particles to the box's
        const auto& b = *box;
        Particles in;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const auto& x = p.position[i];
            if (x[0] >= b[0] && x[1] >= b[1] && x[2] >= b[2] && x[0] <= b[3] && x[1] <= b[4] && x[2] <= b[5])
                in.push_back(p.id[i], p.type[i], x, p.velocity[i], p.density[i], p.pressure[i]);
        }
        return in;
    }
    return p;
}

}  // namespace clsph::device
