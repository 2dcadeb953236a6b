#pragma once
// What the balancer is told each step: per device, what the last step cost; per cell column along
// the split axis, how much work it holds. Plain numbers, so the host can fill them from any device.

#include <cstddef>
#include <vector>

namespace clsph::balance {

// One device's report for the step it just computed.
struct DeviceSample {
  double compute_seconds = 0.0;        // measured compute time, without waits for transfers
  double work = 0.0;                   // the work it had, in the units of ColumnProfile::work
  std::size_t particles = 0;           // particles it owned
  std::size_t capacity_particles = 0;  // how many owned particles fit in its memory; 0 = unlimited
};

// The split axis column by column. `work` is already weighted (see column_work, or
// neighbour-candidate counts); `particles` is used only for the capacity check.
struct ColumnProfile {
  std::vector<double> work;
  std::vector<std::size_t> particles;
  // Where a cut may go: cut_allowed[c] for a cut before column c (columns + 1 entries, 0 and
  // columns always allowed); empty: anywhere. The host forbids cuts that would leave a slab
  // without data it needs (boundary ghost nodes beyond the halo, clsph's mDBC).
  std::vector<char> cut_allowed;
};

// Cost of a boundary particle relative to a fluid one. With dynamic boundary conditions boundary
// particles compute density (one neighbour loop) but no forces (the second, heavier loop), so they
// cost a fraction of a fluid particle: about 0.4 on the GPUs we have profiled. A default, not a
// constant of nature: the host may measure its kernels and pass its own weight.
inline constexpr double default_boundary_weight = 0.4;

// Weighted work of one column: fluid + boundary_weight * boundary.
double column_work(std::size_t fluid, std::size_t boundary,
                   double boundary_weight = default_boundary_weight);

// Work and particles of each slab [cuts[d], cuts[d+1]); cuts has devices+1 entries.
std::vector<double> slab_work(const std::vector<std::size_t>& cuts, const ColumnProfile& profile);
std::vector<std::size_t> slab_particles(const std::vector<std::size_t>& cuts,
                                        const ColumnProfile& profile);

// Equal column widths (they differ by at most one): the `off` mode, and a safe start.
std::vector<std::size_t> equal_width_cuts(std::size_t devices, std::size_t columns);

}  // namespace clsph::balance
