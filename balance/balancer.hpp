#pragma once
// The time-prediction balancer: every step, where the slab cuts between devices go so that every
// device finishes its step at the same time.
//
// Each device's last steps predict its next one through a fitted time model (time_model.hpp); the
// cuts are placed to minimise the largest predicted time over the column work profile
// (cut_search.hpp), and move only when that gains enough, by a bounded number of columns, within
// the minimum width and each device's memory. Pure host arithmetic: no OpenCL type in here.
//
//   Balancer balancer(devices, columns, options);
//   cuts = balancer.initial_cuts(profile, capacities);
//   every step: run with cuts, measure, then cuts = balancer.step(samples, profile).cuts;

#include <cstddef>
#include <string_view>
#include <vector>

#include "balance/cut_search.hpp"
#include "balance/imbalance.hpp"
#include "balance/inputs.hpp"
#include "balance/options.hpp"
#include "balance/time_model.hpp"

namespace clsph::balance {

// Why the cuts are what they are after a step.
enum class Reason {
  moved,            // the best plan gained at least the threshold; cuts moved toward it
  repaired,         // the cuts broke a guard rail (capacity, minimum width) and had to move
  below_threshold,  // no reachable plan gains the threshold: not worth a migration
  no_model_yet,     // no device has reported a usable time yet
  fixed_by_mode,    // mode static or off: cuts never move
  infeasible,       // no placement fits the capacities: cuts kept, the host must react
};
std::string_view to_string(Reason reason);

struct Decision {
  std::vector<std::size_t> cuts;          // devices+1 entries, for the next step
  std::vector<double> predicted_seconds;  // per device under these cuts (0 for an idle device)
  double predicted_max = 0.0;             // the predicted step time
  double predicted_gain = 0.0;            // relative gain of the best plan over the old cuts
  double gain_threshold = 0.0;            // what the gain had to beat (Options::gain_threshold)
  bool moved = false;
  Reason reason = Reason::no_model_yet;
};

class Balancer {
 public:
  Balancer(std::size_t devices, std::size_t columns, Options options = {});

  // A calibration run's result for one device (its step time = fixed + per_unit * work), measured
  // before the first step: it seeds the device's model, and once every device has one the first
  // cut follows it instead of assuming equal speeds.
  void calibrate(std::size_t device, double fixed_seconds, double seconds_per_unit);
  // Cuts before any step: by the calibrated models where every device has one (dynamic, static),
  // otherwise equal work per device (dynamic, static) or equal widths (off), respecting the
  // minimum width and the capacities (one per device, or empty for unlimited).
  std::vector<std::size_t> initial_cuts(const ColumnProfile& profile,
                                        const std::vector<std::size_t>& capacity_particles = {});

  // Feed the step just run with cuts() and get the cuts for the next one. `profile` is the column
  // profile the next step will start from.
  Decision step(const std::vector<DeviceSample>& samples, const ColumnProfile& profile);

  const std::vector<std::size_t>& cuts() const { return cuts_; }
  // The cuts a checkpoint was written with, in place of initial_cuts' (a restart goes on from them).
  void restore_cuts(const std::vector<std::size_t>& cuts) { cuts_ = cuts; }
  const TimeModel& model(std::size_t device) const { return models_.at(device); }
  const Options& options() const { return options_; }

 private:
  // Each device's predicted cost; a device that never reported a time borrows the mean model of
  // those that did (an optimistic guess, corrected after its first step).
  std::vector<SlabCost> slab_costs() const;
  double gain_threshold() const;  // options_.gain_threshold, or lower where the models are precise
  void idle_empty_slabs(std::vector<std::size_t>& cuts, const ColumnProfile& profile) const;
  std::vector<CutWindow> movement_windows() const;
  void check_profile(const ColumnProfile& profile) const;

  std::size_t columns_;
  Options options_;
  std::vector<TimeModel> models_;
  std::vector<std::size_t> capacity_;
  std::vector<std::size_t> cuts_;
  std::vector<bool> calibrated_;
};

}  // namespace clsph::balance
