// Scan: reduce-then-scan over tiles of WG * ITEMS elements, recursing on the tile sums (see
// kernels/scan.cl). Each recursion level keeps its own small buffer of tile sums.
#include "device/primitives.hpp"

#include "device/primitives_launch.hpp"
#include "device/sizing.hpp"

#include "clsph/error.hpp"

#include <deque>
#include <vector>

namespace clsph::device {
namespace {

using sizing::scan_tiles_local_bytes;

// kernels/scan.cl: what an input element counts as (its value, whether non-zero, whether it starts
// a run of equal values).
constexpr cl_uint kValues = 0, kFlags = 1, kStarts = 2;
// Tile sums each work-group of the tiles adds up itself, per work-item, at most (a few loads).
constexpr std::size_t kFoldedTiles = 4;

}  // namespace

struct Scan::Impl {
    cl_rt::Device& dev;
    Config config;
    std::size_t tile = 0;
    cl::Kernel reduce, tiles;
    // sums[level]: tile sums of that level, scanned in place. A deque: deeper levels are added
    // while a shallower one is referenced, and growing a deque keeps references valid.
    std::deque<cl_rt::Buffer> sums;

    Impl(cl_rt::Device& device, Config c) : dev(device), config(std::move(c)) {
        const std::size_t wg0 = config.work_group ? config.work_group : dev.work_group_size(256);
        if (config.items == 0) {
            // 16 per work-item measured best on an H200 (BENCHMARKS.md); fewer where local memory is short.
            config.items = sizing::scan_items(wg0, dev.quirks().usable_local_memory);
        }
        if (config.items % 4 != 0)
            throw Error("scan: items per work-item must be a multiple of 4, not " + std::to_string(config.items));
        if (scan_tiles_local_bytes(wg0, config.items) > dev.quirks().usable_local_memory)
            throw Error("scan: tiles of " + std::to_string(wg0 * config.items) + " elements need " +
                        std::to_string(scan_tiles_local_bytes(wg0, config.items)) + " bytes of local memory, more than the " +
                        std::to_string(dev.quirks().usable_local_memory) + " usable on " + dev.label());
        config.work_group = resolve_work_group(dev, config.work_group, 256, [&](std::size_t wg) {
            const std::string options = "-DWG=" + std::to_string(wg) + " -DITEMS=" + std::to_string(config.items);
            reduce = dev.kernel("scan.cl", "scan_reduce", options);
            tiles = dev.kernel("scan.cl", "scan_tiles", options);
            return std::vector<cl::Kernel*>{&reduce, &tiles};
        });
        tile = config.work_group * config.items;
    }

    // Scans n elements of `in` into `out` (n + 1 elements); level 0 is the caller's scan, deeper
    // levels scan tile sums in place.
    void run(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n, cl_uint flags, std::size_t level) {
        if (n == 0) {
            dev.fill(out, cl_uint{0}, 1);
            return;
        }
        const std::size_t groups = (n + tile - 1) / tile;
        const std::size_t wg = config.work_group;
        if (groups > 1) {
            if (sums.size() <= level) sums.resize(level + 1);
            ensure_capacity(dev, sums[level], (groups + 1) * sizeof(cl_uint), "scan tile sums");
            cl_rt::Buffer& s = sums[level];
            set_args(reduce, in.get(), as_uint(n), flags, s.get());
            dev.launch(config.name + ".reduce", reduce, groups * wg, wg);
            // Few tiles: each work-group of the tiles adds up the sums before its own (has_offsets
            // 2), a launch or more fewer than scanning them first.
            const bool fold = config.fold_offsets && groups <= kFoldedTiles * wg;
            if (!fold) run(s, s, groups, 0, level + 1);
            set_args(tiles, in.get(), out.get(), as_uint(n), flags, s.get(), cl_uint{fold ? 2u : 1u});
        } else {
            // One tile: no offsets to add (out stands in for the unused offsets argument).
            set_args(tiles, in.get(), out.get(), as_uint(n), flags, out.get(), cl_uint{0});
        }
        dev.launch(config.name + ".tiles", tiles, groups * wg, wg);
    }

    void checked_run(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n, cl_uint flags) {
        require_elements("scan input", in, n);
        require_elements("scan output", out, n + 1);
        if (flags == kStarts && in.get()() == out.get()())
            throw Error("scan of run starts: the input and the output must be different buffers");
        run(in, out, n, flags, 0);
    }
};

Scan::Scan(cl_rt::Device& device) : Scan(device, Config{}) {}
Scan::Scan(cl_rt::Device& device, const Config& config) : impl_(std::make_shared<Impl>(device, config)) {}

void Scan::exclusive(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n) { impl_->checked_run(in, out, n, kValues); }

void Scan::exclusive_flags(const cl_rt::Buffer& flags, cl_rt::Buffer& out, std::size_t n) {
    impl_->checked_run(flags, out, n, kFlags);
}

void Scan::exclusive_starts(const cl_rt::Buffer& keys, cl_rt::Buffer& out, std::size_t n) {
    impl_->checked_run(keys, out, n, kStarts);
}

std::uint32_t Scan::exclusive_total(const cl_rt::Buffer& in, cl_rt::Buffer& out, std::size_t n) {
    exclusive(in, out, n);
    std::uint32_t total = 0;
    impl_->dev.read(out, &total, 1, n);
    return total;
}

std::size_t Scan::scratch_bytes() const {
    std::size_t bytes = 0;
    for (const auto& s : impl_->sums) bytes += s.bytes();
    return bytes;
}

std::size_t Scan::tile() const { return impl_->tile; }

}  // namespace clsph::device
