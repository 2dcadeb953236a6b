#pragma once
// Where the cuts go: the placement of contiguous slabs, in device order along the split axis, that
// minimises the largest predicted time. Pure function of the predicted costs and the column profile.
//
// Method: bisection on the step time T. For a given T each device can take, from any start
// column, any slab up to the longest one that fits in T and in its memory; a table of which cut
// positions can still reach the end (built from the last device backwards in O(devices * columns):
// the longest slab from a start only grows as the start moves right) says exactly whether T is
// feasible, including the minimum width and idle devices. The bisection starts between
// the continuous relaxation and the preferred cuts' own time, so it ends in ~10-20 steps.
// Among the plans that meet the smallest feasible T, the cuts closest to a preferred set (the
// current cuts, or a target) are chosen, so cuts that do not need to move stay where they are.

#include <cstddef>
#include <vector>

#include "balance/inputs.hpp"

namespace clsph::balance {

// A device's predicted time for a slab: fixed + per_unit * work when it owns any column, 0 when
// it is idle (an idle device takes no part in the step).
struct SlabCost {
  double fixed_seconds = 0.0;
  double seconds_per_unit = 0.0;
  std::size_t capacity_particles = 0;  // 0 = unlimited
  bool may_idle = true;                 // false: the device always keeps at least min_columns

  double seconds(double work, bool empty) const {
    return empty ? 0.0 : fixed_seconds + seconds_per_unit * work;
  }
};

// Prefix sums of the column profile: the work and particles of any column range in O(1).
class ColumnSums {
 public:
  explicit ColumnSums(const ColumnProfile& profile);
  std::size_t columns() const { return work_.size() - 1; }
  double work(std::size_t begin, std::size_t end) const { return work_[end] - work_[begin]; }
  std::size_t particles(std::size_t begin, std::size_t end) const {
    return particles_[end] - particles_[begin];
  }
  // Whether [begin, end) holds at most work_limit work and capacity particles (0 = unlimited).
  bool fits(std::size_t begin, std::size_t end, double work_limit, std::size_t capacity) const;
  // Last end >= begin for which fits() holds.
  std::size_t furthest_end(std::size_t begin, double work_limit, std::size_t capacity) const;
  // Whether an inner cut may sit before column c (ColumnProfile::cut_allowed).
  bool cut_allowed(std::size_t c) const {
    return cut_allowed_.empty() || c == 0 || c >= columns() || cut_allowed_[c] != 0;
  }

 private:
  std::vector<char> cut_allowed_;
  std::vector<double> work_;             // work_[c] = work of columns [0, c)
  std::vector<std::size_t> particles_;  // same for particles
};

// Inclusive range where one inner cut may go this step (bounded movement).
struct CutWindow {
  std::size_t lo = 0;
  std::size_t hi = 0;
};

struct Plan {
  bool feasible = false;  // false: no placement fits the capacities and the minimum width
  std::vector<std::size_t> cuts;
  double makespan = 0.0;  // largest predicted time under these cuts
};

// The best cuts. `preferred` (devices+1 entries) breaks ties between equally good plans;
// `windows` (devices+1 entries, or empty for none) bounds where each cut may go.
Plan place_cuts(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                std::size_t min_columns, const std::vector<std::size_t>& preferred,
                const std::vector<CutWindow>& windows = {});

// Predicted time of every device under the given cuts.
std::vector<double> predicted_seconds(const std::vector<SlabCost>& devices,
                                      const ColumnSums& columns,
                                      const std::vector<std::size_t>& cuts);

// Whether the cuts keep every guard rail: non-empty slabs at least min_columns wide and every
// device within its capacity.
bool respects_guard_rails(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                          std::size_t min_columns, const std::vector<std::size_t>& cuts);

}  // namespace clsph::balance
