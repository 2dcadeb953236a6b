#include "device/grid.hpp"

#include "clsph/error.hpp"

#include <cmath>
#include <sstream>

namespace clsph::device {
namespace {
unsigned bits_for(std::uint64_t count) {  // bits needed to hold values 0..count-1
    unsigned b = 0;
    while ((std::uint64_t{1} << b) < count) ++b;
    return b;
}
const char* axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : "z"; }
}  // namespace

int reach_for(double support, double dp) { return support >= 3.5 * dp ? 2 : 1; }

Grid::Grid(const Box& domain, double support, int split_axis, std::array<bool, 3> periodic, int reach)
    : domain_(domain), periodic_(periodic), reach_(reach) {
    if (reach < 1 || reach > 2) throw SceneError("grid: reach must be 1 or 2");
    if (!(support > 0) || !std::isfinite(support)) throw SceneError("grid: kernel support must be positive");
    std::array<double, 3> ext{};
    for (int k = 0; k < 3; ++k) {
        ext[k] = domain.hi[k] - domain.lo[k];
        if (!(ext[k] > 0) || !std::isfinite(ext[k]))
            throw SceneError(std::string("domain: max.") + axis_name(k) + " must be greater than min." + axis_name(k));
    }
    if (split_axis < 0) {
        split_axis = 0;
        for (int k = 1; k < 3; ++k)
            if (ext[k] > ext[split_axis]) split_axis = k;
    }
    if (split_axis > 2) throw SceneError("grid: split axis must be x, y or z");
    if (periodic[split_axis])
        throw SceneError(std::string("domain: axis ") + axis_name(split_axis) +
                         " is periodic but is the split axis between devices; choose another split axis");
    int others[2], m = 0;
    for (int k = 0; k < 3; ++k)
        if (k != split_axis) others[m++] = k;
    if (periodic[others[0]] && periodic[others[1]])
        throw SceneError("domain: at most one axis besides the split axis may be periodic in this version");
    // The periodic axis (if any) takes the middle key position, where neighbour rows wrap whole;
    // the least significant position b must not wrap (its rows are contiguous key ranges).
    int a = others[0], b = others[1];
    if (periodic[b]) std::swap(a, b);
    axis_ = {split_axis, a, b};

    std::array<std::uint32_t, 3> n{};
    std::array<double, 3> cell{};
    for (int pos = 0; pos < 3; ++pos) {
        const int k = axis_[pos];
        // Non-periodic: floor + 1 so the domain is closed (a particle exactly on the max face is inside).
        const double edge = pos == 0 ? support : support / reach;  // s keeps whole supports
        const double cells = periodic[k] ? std::floor(ext[k] / edge) : std::floor(ext[k] / edge) + 1.0;
        if (cells > 1e9) throw SceneError("domain: far too many cells along " + std::string(axis_name(k)));
        n[pos] = static_cast<std::uint32_t>(std::max(1.0, cells));
        cell[pos] = periodic[k] ? ext[k] / n[pos] : edge;
        if (periodic[k] && n[pos] < static_cast<std::uint32_t>(2 * reach + 1))
            throw SceneError(std::string("domain: periodic axis ") + axis_name(k) +
                             " must be at least 3 kernel supports long (with run.list_buffer: 3 supports and buffers)");
    }
    const unsigned bb = bits_for(std::uint64_t{n[2]} + 2 * reach), ba = bits_for(n[1]), bs = bits_for(n[0]);
    key_bits_ = std::max(1u, bb + ba + bs);
    if (key_bits_ > 32) {
        std::ostringstream o;
        o << "domain: the grid needs " << n[0] << " x " << n[1] << " x " << n[2]
          << " cells, whose keys need " << key_bits_
          << " bits; clsph uses 32-bit cell keys: enlarge dp (the kernel support) or shrink the domain";
        throw SceneError(o.str());
    }
    p_.cell_s = static_cast<float>(cell[0]);
    p_.cell_a = static_cast<float>(cell[1]);
    p_.cell_b = static_cast<float>(cell[2]);
    p_.n_s = n[0];
    p_.n_a = n[1];
    p_.n_b = n[2];
    p_.shift_a = bb;
    p_.shift_s = bb + ba;
    p_.mask_b = (1u << bb) - 1u;
    p_.mask_a = ba == 0 ? 0u : (1u << ba) - 1u;
    p_.ext_s = static_cast<float>(ext[axis_[0]]);
    p_.ext_a = static_cast<float>(ext[axis_[1]]);
    p_.ext_b = static_cast<float>(ext[axis_[2]]);
    p_.periodic_a = periodic[axis_[1]] ? 1u : 0u;
    p_.invalid_key = key_bits_ == 32 ? 0xffffffffu : (1u << key_bits_) - 1u;
}

std::uint64_t Grid::cell_count() const { return std::uint64_t{p_.n_s} * p_.n_a * p_.n_b; }

std::array<double, 3> Grid::cell_size_xyz() const {
    std::array<double, 3> c{};
    c[axis_[0]] = p_.cell_s;
    c[axis_[1]] = p_.cell_a;
    c[axis_[2]] = p_.cell_b;
    return c;
}

std::uint32_t Grid::key(std::uint32_t s, std::uint32_t a, std::uint32_t b) const {
    const std::uint32_t high = p_.shift_s >= 32 ? 0u : (s << p_.shift_s);  // n_s == 1 uses no bits
    return high | (a << p_.shift_a) | (b + static_cast<std::uint32_t>(reach_));
}

std::array<std::uint32_t, 3> Grid::cell_of_key(std::uint32_t k) const {
    return {p_.shift_s >= 32 ? 0u : k >> p_.shift_s, (k >> p_.shift_a) & p_.mask_a,
            (k & p_.mask_b) - static_cast<std::uint32_t>(reach_)};
}

bool Grid::locate_axis(int pos, double x, std::uint32_t& cell, float& offset) const {
    const double cells[3] = {p_.cell_s, p_.cell_a, p_.cell_b};
    const std::uint32_t counts[3] = {p_.n_s, p_.n_a, p_.n_b};
    const int k = axis_[pos];
    double rel = x - domain_.lo[k];
    if (periodic_[k]) {  // wrap into [0, L) first; cells divide a periodic axis exactly
        const double len = cells[pos] * counts[pos];
        rel -= std::floor(rel / len) * len;
    }
    double ci = std::floor(rel / cells[pos]);
    if (periodic_[k] && ci >= counts[pos]) ci = counts[pos] - 1.0;  // rel rounded up to len
    if (!(ci >= 0) || ci >= counts[pos]) return false;
    cell = static_cast<std::uint32_t>(ci);
    offset = static_cast<float>(rel - (ci + 0.5) * cells[pos]);
    return true;
}

std::uint32_t Grid::key_part(int pos, std::uint32_t cell) const {
    if (pos == 0) return p_.shift_s >= 32 ? 0u : (cell << p_.shift_s);
    if (pos == 1) return cell << p_.shift_a;
    return cell + static_cast<std::uint32_t>(reach_);
}

std::uint32_t Grid::locate(const std::array<double, 3>& x, std::array<float, 3>& offset) const {
    std::uint32_t c[3];
    for (int pos = 0; pos < 3; ++pos) {
        const int k = axis_[pos];
        if (!locate_axis(pos, x[k], c[pos], offset[k])) {
            offset = {0, 0, 0};
            return p_.invalid_key;
        }
    }
    return key(c[0], c[1], c[2]);
}

std::array<double, 3> Grid::position(std::uint32_t k, const std::array<float, 3>& offset) const {
    const auto c = cell_of_key(k);
    const double cells[3] = {p_.cell_s, p_.cell_a, p_.cell_b};
    std::array<double, 3> x{};
    for (int pos = 0; pos < 3; ++pos) {
        const int ax = axis_[pos];
        x[ax] = domain_.lo[ax] + (c[pos] + 0.5) * cells[pos] + static_cast<double>(offset[ax]);
    }
    return x;
}

std::string Grid::kernel_options() const {
    return "-DAXIS_S=" + std::to_string(axis_[0]) + " -DAXIS_A=" + std::to_string(axis_[1]) +
           " -DAXIS_B=" + std::to_string(axis_[2]) + " -DCLSPH_REACH=" + std::to_string(reach_);
}

}  // namespace clsph::device
