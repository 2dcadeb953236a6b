#pragma once
// A per-step CSV log that makes every balancing decision explainable: what each device was
// predicted to take, what it took, with how much work, and where the cuts went.
//
// Columns (D devices, one row per step):
//   step, imbalance, predicted_max, predicted_gain, moved, reason,
//   then per device d: d<d>_measured_s, d<d>_predicted_s, d<d>_next_s, d<d>_work, d<d>_particles,
//   then cut0 .. cut<D>.
// measured_s/work/particles describe the step just run; predicted_s is what the previous row
// predicted for it (empty on the first row); next_s and the cuts are the decision for the next
// step. imbalance = max/mean of measured_s over the devices that had work (an idle device is not
// late); predicted_max, predicted_gain, moved and reason come from the Decision.

#include <cstddef>
#include <ostream>
#include <vector>

#include "balance/balancer.hpp"
#include "balance/imbalance.hpp"

namespace clsph::balance {

class BalanceLog {
 public:
  BalanceLog(std::ostream& out, std::size_t devices);

  void write_header();
  // Writes the header first if it has not been written yet.
  void write(std::size_t step, const std::vector<DeviceSample>& measured, const Decision& decision);

 private:
  std::ostream& out_;
  std::size_t devices_;
  bool header_written_ = false;
  std::vector<double> predicted_;  // the previous decision's prediction for the step now measured
};

}  // namespace clsph::balance
