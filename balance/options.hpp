#pragma once
// The balancer's knobs and their defaults. Every default is chosen for a few hundred columns, two to
// eight devices, and step times that jitter by a few percent; docs/balance.md says why.

#include <cstddef>
#include <optional>
#include <string_view>

namespace clsph::balance {

enum class Mode {
  dynamic,  // default: re-cut every step from the devices' time models
  static_,  // cut once by work (equal work per device), never move
  off,      // equal column widths, never move: for experiments and tests
};

std::string_view to_string(Mode mode);
std::optional<Mode> mode_from_string(std::string_view text);  // "dynamic" | "static" | "off"

// How each device's time model is fitted (see time_model.hpp).
struct ModelOptions {
  // Steps kept in the sliding window.
  std::size_t window = 64;
  // Weight of a sample one step older, relative to the newer one. 0.98 over 64 steps gives about
  // 55 effective samples: +-5 % jitter averages to 0.4 %, small next to gain_threshold, so jitter
  // alone seldom moves a cut. A device that changes speed suddenly does not wait for forgetting
  // (see change_threshold); a gradual drift is followed with a time constant of ~50 steps.
  double forgetting = 0.98;
  // Ridge toward the anchor's fixed/per-unit split, as a relative work variance: a window whose
  // work varies by sqrt(ridge) = 10 % (standard deviation) weighs as much as the anchor. Below
  // that the split comes mostly from the anchor (the data cannot tell fixed from per-unit cost),
  // but the prediction at the current work always follows the data.
  double ridge = 1e-2;
  // A prediction error above this (relative), at a work the window has already seen, twice in a row
  // and in the same direction, means the device changed speed: the window restarts.
  double change_threshold = 0.25;
  // Work is never free: at least this share of the time at the window's mean work scales with it.
  double min_per_unit_share = 0.05;
  // Samples before the model reports its prediction error (TimeModel::prediction_error).
  std::size_t noise_min_samples = 8;
};

struct Options {
  Mode mode = Mode::dynamic;
  // Narrowest non-empty slab, in columns: the halo width (the neighbours read the first and last
  // columns). A device may still be left idle, with no column at all.
  std::size_t min_columns = 1;
  // Whether the best plan may leave a device with no column at all. An idle device is not measured
  // any more, so its model cannot notice that it would now help; one noisy step must therefore not
  // idle a device: only a device whose model rests on a calibration (Balancer::calibrate) or on at
  // least idle_min_samples measured steps may be idled. Engines that cannot afford idling at all
  // turn this off.
  bool allow_idle = true;
  std::size_t idle_min_samples = 8;
  // Cuts move only when the best plan would lower the predicted step time (the slowest device), or
  // the predicted imbalance, by at least this fraction: a move costs a migration, and jitter must
  // not make cuts wander. 1.5 % is about four standard errors of a prediction at the defaults.
  double gain_threshold = 0.015;
  // Once every busy device's model knows its prediction error (TimeModel::prediction_error), the
  // threshold becomes threshold_standard_errors times the largest, kept within
  // [min_gain_threshold, gain_threshold]: devices whose times jitter by 0.1 % (two H200s) can be
  // balanced to a fraction of a percent, while noisy ones keep the full threshold.
  double threshold_standard_errors = 4.0;
  double min_gain_threshold = 0.003;
  // At most this many columns per cut per step, so a migration stays a small copy; 0 = unbounded.
  // Broken guard rails (a device over its capacity) are repaired even when that needs more.
  std::size_t max_move_columns = 16;
  ModelOptions model;
};

}  // namespace clsph::balance
