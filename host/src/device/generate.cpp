#include "device/generate.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"

#include <algorithm>

namespace clsph::device {

using cl_rt::set_args;
using scene::LatticeAxis;
using scene::LatticePiece;
using scene::LatticePlan;

namespace {

constexpr std::uint32_t kOutside = 0xffffffffu;

int key_position(const Grid& grid, int axis) {
    for (int p = 0; p < 3; ++p)
        if (grid.axis(p) == axis) return p;
    return 0;
}

// Per coordinate: the key part of its cell (kOutside outside the domain) and the offset from the
// cell centre, exactly as Grid::locate computes them.
struct AxisCode {
    std::vector<std::uint32_t> part;
    std::vector<float> offset;
};

AxisCode encode(const LatticeAxis& ax, const Grid& grid) {
    const int kp = key_position(grid, ax.axis);
    AxisCode c;
    c.part.resize(ax.size());
    c.offset.resize(ax.size());
    for (std::size_t i = 0; i < ax.size(); ++i) {
        std::uint32_t cell = 0;
        float off = 0.0f;
        if (grid.locate_axis(kp, ax.x[i], cell, off)) {
            c.part[i] = grid.key_part(kp, cell);
            c.offset[i] = off;
        } else {
            c.part[i] = kOutside;
            c.offset[i] = 0.0f;
        }
    }
    return c;
}

template <class T>
cl_rt::Buffer upload(cl_rt::Device& d, const std::vector<T>& v, const char* what) {
    cl_rt::Buffer b = d.alloc(std::max<std::size_t>(v.size(), 1) * sizeof(T), what);
    d.write(b, v.data(), v.size());
    return b;
}

}  // namespace

PlaneRange planes_of(const LatticePiece& piece, const Grid& grid, std::size_t first_col, std::size_t end_col) {
    // Planes below the domain count as column -1 (the first slab's), above it as the last column.
    const auto& ax = piece.axis[0];
    const std::size_t columns = grid.params().n_s;
    const int s = grid.axis(0);
    auto column = [&](std::size_t i) -> long long {
        std::uint32_t cell = 0;
        float off = 0.0f;
        if (grid.locate_axis(0, ax.x[i], cell, off)) return cell;
        return ax.x[i] < grid.domain().lo[s] ? -1 : static_cast<long long>(columns) - 1;
    };
    const long long lo = first_col == 0 ? -1 : static_cast<long long>(first_col);
    const long long hi = static_cast<long long>(end_col);
    PlaneRange r{ax.size(), ax.size()};
    if (end_col <= first_col) return {0, 0};
    for (std::size_t i = 0; i < ax.size(); ++i) {
        const long long c = column(i);
        if (c >= lo && r.first == ax.size()) r.first = i;
        if (c >= hi) {
            r.end = i;
            break;
        }
    }
    if (r.first > r.end) r.first = r.end;
    return r;
}

std::vector<std::uint64_t> slab_counts(const LatticePlan& plan, const Grid& grid, std::size_t first_col,
                                       std::size_t end_col) {
    std::vector<std::uint64_t> out;
    for (const auto& piece : plan.pieces) {
        const auto r = planes_of(piece, grid, first_col, end_col);
        std::uint64_t n = 0;
        for (std::size_t i = r.first; i < r.end; ++i) n += piece.plane_count[i];
        out.push_back(n);
    }
    return out;
}

Particles slab_particles(const LatticePlan& plan, const Grid& grid, std::size_t first_col, std::size_t end_col) {
    std::vector<PlaneRange> ranges;
    for (const auto& piece : plan.pieces) ranges.push_back(planes_of(piece, grid, first_col, end_col));
    return plan.particles([&](const LatticePiece& piece, std::size_t plane) {
        const auto& r = ranges[static_cast<std::size_t>(&piece - plan.pieces.data())];
        return plane >= r.first && plane < r.end;
    });
}

Generator::Generator(cl_rt::Device& device, const Grid& grid)
    : device_(device), grid_(grid), scan_(device), wg_(device.work_group_size(256)) {
    const std::string opts = grid.kernel_options();
    boundary_k_ = device.kernel("generate.cl", "generate_boundary", opts);
    flags_k_ = device.kernel("generate.cl", "generate_fluid_flags", opts);
    write_k_ = device.kernel("generate.cl", "generate_fluid_write", opts);
}

std::size_t Generator::generate(const LatticePlan& plan, ParticleStore& store, std::size_t first_col,
                                std::size_t end_col) {
    auto& d = device_;
    const auto counts = slab_counts(plan, grid_, first_col, end_col);
    std::uint64_t total = 0;
    for (auto c : counts) total += c;
    store.reserve(static_cast<std::size_t>(total));
    const cl_uint invalid = grid_.params().invalid_key;
    std::uint64_t out = 0;
    for (std::size_t k = 0; k < plan.pieces.size(); ++k) {
        const LatticePiece& piece = plan.pieces[k];
        const PlaneRange r = planes_of(piece, grid_, first_col, end_col);
        if (counts[k] == 0 || r.end <= r.first) continue;
        std::uint64_t id_first = piece.first_id;
        for (std::size_t i = 0; i < r.first; ++i) id_first += piece.plane_count[i];
        const std::size_t n0 = piece.axis[0].size(), n1 = piece.axis[1].size(), n2 = piece.axis[2].size();
        AxisCode code[3];
        cl_rt::Buffer part[3], off[3], mask[3];
        for (int p = 0; p < 3; ++p) {
            code[p] = encode(piece.axis[p], grid_);
            part[p] = upload(d, code[p].part, "set-up tables");
            off[p] = upload(d, code[p].offset, "set-up tables");
            mask[p] = upload(d, piece.mask[p], "set-up tables");
        }
        const cl_uint comp[3] = {static_cast<cl_uint>(piece.axis[0].axis), static_cast<cl_uint>(piece.axis[1].axis),
                                 static_cast<cl_uint>(piece.axis[2].axis)};
        const auto density = upload(d, piece.density, "set-up tables");
        const int pz = piece.pos_of_axis(2);
        const std::size_t nz = piece.axis[pz].size();
        const cl_uint none = static_cast<cl_uint>(plan.blocks);
        if (!piece.fluid) {
            std::vector<std::uint32_t> plane_start(r.end - r.first + 1, 0);
            for (std::size_t i = r.first; i < r.end; ++i)
                plane_start[i - r.first + 1] = plane_start[i - r.first] + static_cast<std::uint32_t>(piece.plane_count[i]);
            std::vector<std::uint32_t> layer1_before(n1 + 1, 0), layer2_at;
            for (std::size_t j = 0; j < n1; ++j) layer1_before[j + 1] = layer1_before[j] + piece.axis[1].layer[j];
            for (std::size_t j = 0; j < n2; ++j)
                if (piece.axis[2].layer[j]) layer2_at.push_back(static_cast<std::uint32_t>(j));
            const auto starts = upload(d, plane_start, "set-up tables");
            const auto layer0 = upload(d, piece.axis[0].layer, "set-up tables");
            const auto before = upload(d, layer1_before, "set-up tables");
            const auto at = upload(d, layer2_at, "set-up tables");
            set_args(boundary_k_, static_cast<std::size_t>(counts[k]), static_cast<std::size_t>(out),
                     static_cast<std::size_t>(id_first), r.end - r.first, r.first, starts, n1, n2, layer2_at.size(),
                     layer0, before, at, part[0], part[1], part[2], off[0], off[1], off[2], comp[0], comp[1], comp[2],
                     invalid, mask[0], mask[1], mask[2], none, density, nz, static_cast<cl_uint>(pz), store.pos,
                     store.velrho, store.accel, store.id);
            d.launch("setup.boundary", boundary_k_, static_cast<std::size_t>(counts[k]), wg_);
        } else {
            std::vector<cl_long> layer, any;
            for (const auto& t : piece.near)
                for (int p = 0; p < 3; ++p) {
                    layer.insert(layer.end(), t.layer[p].begin(), t.layer[p].end());
                    any.insert(any.end(), t.any[p].begin(), t.any[p].end());
                }
            const auto layer_b = upload(d, layer, "set-up tables");
            const auto any_b = upload(d, any, "set-up tables");
            std::vector<cl_float4> vel(piece.velocity.size());
            for (std::size_t b = 0; b < vel.size(); ++b)
                vel[b] = {{piece.velocity[b][0], piece.velocity[b][1], piece.velocity[b][2], 0.0f}};
            const auto vel_b = upload(d, vel, "set-up tables");
            const std::uint64_t candidates = static_cast<std::uint64_t>(r.end - r.first) * n1 * n2;
            const std::uint64_t chunk = std::max<std::uint64_t>(1, std::min<std::uint64_t>(candidates, store.capacity()));
            std::uint64_t written = 0;
            for (std::uint64_t first = 0; first < candidates; first += chunk) {
                const auto m = static_cast<std::size_t>(std::min(chunk, candidates - first));
                set_args(flags_k_, m, static_cast<std::size_t>(first), r.first, n0, n1, n2, piece.near.size(), layer_b,
                         any_b, static_cast<cl_long>(scene::kNearLimit), store.keys);
                d.launch("setup.fluid_flags", flags_k_, m, wg_);
                scan_.exclusive_flags(store.keys, store.vals, m);
                cl_uint kept = 0;
                d.read(store.vals, &kept, 1, m);
                set_args(write_k_, m, static_cast<std::size_t>(first), r.first, n1, n2, static_cast<std::size_t>(out),
                         static_cast<std::size_t>(id_first), static_cast<std::size_t>(written), store.keys, store.vals,
                         vel_b, part[0], part[1], part[2], off[0], off[1], off[2], comp[0], comp[1], comp[2], invalid,
                         mask[0], mask[1], mask[2], none, density, nz, static_cast<cl_uint>(pz), store.pos,
                         store.velrho, store.accel, store.id);
                d.launch("setup.fluid_write", write_k_, m, wg_);
                written += kept;
            }
            if (written != counts[k])
                throw Error("set-up on " + d.label() + ": fluid block " + std::to_string(piece.source) + " gave " +
                            std::to_string(written) + " particles in columns [" + std::to_string(first_col) + ", " +
                            std::to_string(end_col) + "), the plan counts " + std::to_string(counts[k]));
        }
        d.finish();  // the tables go out of scope
        out += counts[k];
    }
    store.ranges = ParticleRanges{0, static_cast<std::size_t>(total), 0};
    return static_cast<std::size_t>(total);
}

}  // namespace clsph::device
