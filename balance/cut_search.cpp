#include "balance/cut_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace clsph::balance {

ColumnSums::ColumnSums(const ColumnProfile& profile)
    : work_(profile.work.size() + 1, 0.0), particles_(profile.work.size() + 1, 0) {
  if (profile.particles.size() != profile.work.size())
    throw std::invalid_argument("balance: column profile needs work and particles per column");
  if (!profile.cut_allowed.empty() && profile.cut_allowed.size() != profile.work.size() + 1)
    throw std::invalid_argument("balance: cut_allowed needs an entry per cut position (columns + 1)");
  cut_allowed_ = profile.cut_allowed;
  for (std::size_t c = 0; c < profile.work.size(); ++c) {
    // Negative work would break the monotone prefix sums the search relies on.
    work_[c + 1] = work_[c] + std::max(0.0, profile.work[c]);
    particles_[c + 1] = particles_[c] + profile.particles[c];
  }
}

bool ColumnSums::fits(std::size_t begin, std::size_t end, double work_limit,
                      std::size_t capacity) const {
  return work_[end] <= work_[begin] + work_limit &&
         (capacity == 0 || particles_[end] <= particles_[begin] + capacity);
}

std::size_t ColumnSums::furthest_end(std::size_t begin, double work_limit,
                                     std::size_t capacity) const {
  // fits() is monotone in end: binary search for the last end that fits.
  std::size_t lo = begin, hi = columns();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (fits(begin, mid, work_limit, capacity))
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

namespace {

constexpr double unbounded = std::numeric_limits<double>::infinity();

// The feasibility table for one step time T and the plan read back from it.
class Search {
 public:
  Search(const std::vector<SlabCost>& devices, const ColumnSums& columns, std::size_t min_columns,
         const std::vector<CutWindow>& windows)
      : devices_(devices), columns_(columns), min_width_(std::max<std::size_t>(1, min_columns)),
        windows_(windows),
        reach_(devices.size() + 1, std::vector<char>(columns.columns() + 1, 0)) {}

  // Fills reach_[k][c]: cut k may sit at column c and devices k.. can cover [c, N) within T.
  bool feasible(double step_time) {
    step_time_ = step_time;
    const std::size_t n = columns_.columns(), count = devices_.size();
    std::fill(reach_[count].begin(), reach_[count].end(), 0);
    reach_[count][n] = 1;
    std::vector<std::size_t> reachable_before(n + 2, 0);  // # reachable ends in [0, i)
    for (std::size_t d = count; d-- > 0;) {
      const std::vector<char>& next = reach_[d + 1];
      for (std::size_t e = 0; e <= n; ++e) reachable_before[e + 1] = reachable_before[e] + next[e];
      // The furthest end only moves forward as the start does: one sweep per device.
      std::size_t end = 0;
      for (std::size_t c = 0; c <= n; ++c) {
        char ok = 0;
        if (allowed(d, c)) {
          ok = devices_[d].may_idle ? next[c] : 0;  // device d idle
          if (!ok && step_time >= devices_[d].fixed_seconds) {
            const double work_limit = work_limit_of(d, step_time);
            end = std::max(end, c);
            while (end < n &&
                   columns_.fits(c, end + 1, work_limit, devices_[d].capacity_particles))
              ++end;
            const std::size_t first = c + min_width_;
            if (first <= end) ok = reachable_before[end + 1] > reachable_before[first];
          }
        }
        reach_[d][c] = ok;
      }
    }
    return reach_[0][0] != 0;
  }

  // Reads one plan out of the table of the last feasible() call: cut by cut, the reachable
  // position closest to the preferred one.
  std::vector<std::size_t> cuts_nearest(const std::vector<std::size_t>& preferred) const {
    const std::size_t n = columns_.columns(), count = devices_.size();
    std::vector<std::size_t> cuts(count + 1, 0);
    for (std::size_t d = 0; d < count; ++d) {
      const std::size_t c = cuts[d];
      const std::vector<char>& next = reach_[d + 1];
      const std::size_t want = preferred[d + 1];
      std::size_t best = n + 1;  // none yet
      auto consider = [&](std::size_t e) {
        if (best > n || distance(e, want) < distance(best, want)) best = e;
      };
      const std::size_t first = c + min_width_, last = furthest_end(d, c, step_time_);
      if (first <= last) {
        // Walk outward from the preferred position clamped into [first, last].
        const std::size_t start = std::clamp(want, first, last);
        for (std::size_t e = start + 1; e-- > first;)
          if (next[e]) { consider(e); break; }
        for (std::size_t e = start; e <= last; ++e)
          if (next[e]) { consider(e); break; }
      }
      if (next[c]) consider(c);
      if (best > n) throw std::logic_error("balance: cut search table has no way forward");
      cuts[d + 1] = best;
    }
    return cuts;
  }

 private:
  static std::size_t distance(std::size_t a, std::size_t b) { return a > b ? a - b : b - a; }

  bool allowed(std::size_t cut, std::size_t c) const {
    if (cut == 0) return c == 0;
    if (cut == devices_.size()) return c == columns_.columns();
    if (!columns_.cut_allowed(c)) return false;
    if (windows_.empty()) return true;
    return windows_[cut].lo <= c && c <= windows_[cut].hi;
  }

  // Most work device d can take within step_time (for step_time >= its fixed cost).
  double work_limit_of(std::size_t d, double step_time) const {
    const SlabCost& cost = devices_[d];
    return cost.seconds_per_unit > 0.0 ? (step_time - cost.fixed_seconds) / cost.seconds_per_unit
                                       : unbounded;
  }

  // Last end column of a non-empty slab of device d starting at c that fits in step_time (c when
  // none fits). Uses the same test as the sweep in feasible(), so the two always agree.
  std::size_t furthest_end(std::size_t d, std::size_t c, double step_time) const {
    if (step_time < devices_[d].fixed_seconds) return c;
    return columns_.furthest_end(c, work_limit_of(d, step_time), devices_[d].capacity_particles);
  }

  const std::vector<SlabCost>& devices_;
  const ColumnSums& columns_;
  std::size_t min_width_;
  const std::vector<CutWindow>& windows_;
  std::vector<std::vector<char>> reach_;
  double step_time_ = unbounded;  // of the last feasible() call
};

// A step time some plan surely meets: the preferred cuts' own, when they keep every rule;
// otherwise the slowest device doing all the work alone.
double upper_bound_step_time(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                             std::size_t min_columns, const std::vector<std::size_t>& preferred,
                             const std::vector<CutWindow>& windows) {
  bool usable = respects_guard_rails(devices, columns, min_columns, preferred) &&
                preferred.front() == 0 && preferred.back() == columns.columns();
  for (std::size_t k = 0; usable && k < windows.size(); ++k)
    usable = windows[k].lo <= preferred[k] && preferred[k] <= windows[k].hi;
  double hi = 0.0;
  if (usable) {
    const std::vector<double> seconds = predicted_seconds(devices, columns, preferred);
    hi = *std::max_element(seconds.begin(), seconds.end()) * (1.0 + 1e-12);
  } else {
    for (const SlabCost& cost : devices)
      hi = std::max(hi, cost.seconds(columns.work(0, columns.columns()), false));
  }
  return std::max(hi, 1e-300);
}

// A step time no plan beats: the continuous relaxation, where work divides anywhere and every
// device takes (T - fixed) / per_unit of it.
double lower_bound_step_time(const std::vector<SlabCost>& devices, double total_work,
                             double guess) {
  auto capacity_at = [&](double step_time) {
    double work = 0.0;
    for (const SlabCost& cost : devices) {
      if (step_time <= cost.fixed_seconds) continue;
      if (cost.seconds_per_unit <= 0.0) return unbounded;
      work += (step_time - cost.fixed_seconds) / cost.seconds_per_unit;
    }
    return work;
  };
  double lo = 0.0, hi = guess;
  while (capacity_at(hi) < total_work) hi *= 2.0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (capacity_at(mid) < total_work ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

Plan place_cuts(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                std::size_t min_columns, const std::vector<std::size_t>& preferred,
                const std::vector<CutWindow>& windows) {
  if (devices.empty()) throw std::invalid_argument("balance: need at least one device");
  if (preferred.size() != devices.size() + 1 ||
      (!windows.empty() && windows.size() != devices.size() + 1))
    throw std::invalid_argument("balance: preferred cuts and windows need devices+1 entries");

  Search search(devices, columns, min_columns, windows);
  Plan plan;
  // Bracket the smallest step time tightly: each bisection step costs a full table. In steady
  // state the preferred (current) cuts are nearly optimal, so the bracket starts a few % wide.
  double hi = upper_bound_step_time(devices, columns, min_columns, preferred, windows);
  bool table_at_hi = search.feasible(hi);
  if (!table_at_hi) {
    if (!search.feasible(unbounded)) return plan;  // no time is enough: capacities, windows
    while (!search.feasible(hi)) hi *= 2.0;
    table_at_hi = true;
  }
  double lo = lower_bound_step_time(devices, columns.work(0, columns.columns()), hi);
  if (!(lo < hi)) lo = 0.0;
  for (int iteration = 0; iteration < 100 && hi - lo > 1e-6 * hi; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    table_at_hi = search.feasible(mid);
    (table_at_hi ? hi : lo) = mid;
  }
  if (!table_at_hi) search.feasible(hi);  // the table must describe hi, not an infeasible midpoint

  plan.feasible = true;
  plan.cuts = search.cuts_nearest(preferred);
  const std::vector<double> seconds = predicted_seconds(devices, columns, plan.cuts);
  plan.makespan = *std::max_element(seconds.begin(), seconds.end());
  return plan;
}

std::vector<double> predicted_seconds(const std::vector<SlabCost>& devices,
                                      const ColumnSums& columns,
                                      const std::vector<std::size_t>& cuts) {
  std::vector<double> seconds(devices.size(), 0.0);
  for (std::size_t d = 0; d < devices.size(); ++d)
    seconds[d] = devices[d].seconds(columns.work(cuts[d], cuts[d + 1]), cuts[d] == cuts[d + 1]);
  return seconds;
}

bool respects_guard_rails(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                          std::size_t min_columns, const std::vector<std::size_t>& cuts) {
  for (std::size_t d = 0; d < devices.size(); ++d) {
    if (cuts[d + 1] < cuts[d]) return false;
    const std::size_t width = cuts[d + 1] - cuts[d];
    if (width > 0 && width < min_columns) return false;
    const std::size_t capacity = devices[d].capacity_particles;
    if (capacity > 0 && columns.particles(cuts[d], cuts[d + 1]) > capacity) return false;
  }
  return true;
}

}  // namespace clsph::balance
