#include "device/thin_download.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <cstring>
#include <vector>

namespace clsph::device {

ThinDownload::ThinDownload(cl_rt::Device& device, const Grid& grid)
    : device_(device), grid_(grid), scan_(device), wg_(device.work_group_size(256)) {
    flags_k_ = device.kernel("select.cl", "stride_flags");
    gather_k_ = device.kernel("select.cl", "stride_gather");
}

Particles ThinDownload::download(ParticleStore& store, std::uint32_t stride) {
    auto& d = device_;
    if (stride == 0) throw Error("a thinned download needs a stride of at least 1");
    const std::size_t first = store.ranges.first_owned(), n = store.ranges.owned;
    Particles p;
    if (n == 0) return p;
    // Flags, scanned in place, in the reorder scratch (4 uints per particle of capacity).
    cl_rt::set_args(flags_k_, n, first, cl_uint{stride}, store.id, store.scratch);
    d.launch("download.flags", flags_k_, n, wg_);
    scan_.exclusive(store.scratch, store.scratch, n);
    cl_uint m = 0;
    d.read(store.scratch, &m, 1, n);
    if (m == 0) return p;
    const std::size_t f4 = 4 * sizeof(float);
    cl_rt::Buffer out_pos = d.alloc(m * f4, "thinned frame"), out_vr = d.alloc(m * f4, "thinned frame"),
                  out_id = d.alloc(m * sizeof(std::uint32_t), "thinned frame");
    cl_rt::set_args(gather_k_, n, first, cl_uint{stride}, store.id, store.scratch, store.pos, store.velrho, out_pos,
                    out_vr, out_id);
    d.launch("download.gather", gather_k_, n, wg_);
    std::vector<float> hp(4 * std::size_t{m}), hv(4 * std::size_t{m});
    std::vector<std::uint32_t> hid(m);
    d.read(out_pos, hp.data(), hp.size());
    d.read(out_vr, hv.data(), hv.size());
    d.read(out_id, hid.data(), hid.size());
    p.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
        std::uint32_t key;
        std::memcpy(&key, &hp[4 * i + 3], sizeof key);
        p.position[i] = grid_.position(key, {hp[4 * i], hp[4 * i + 1], hp[4 * i + 2]});
        p.velocity[i] = {hv[4 * i], hv[4 * i + 1], hv[4 * i + 2]};
        p.density[i] = hv[4 * i + 3];
        p.pressure[i] = 0.0f;
        p.id[i] = hid[i] & CLSPH_ID_MASK;
        p.type[i] = static_cast<ParticleType>(hid[i] >> CLSPH_TYPE_SHIFT);
    }
    return p;
}

}  // namespace clsph::device
