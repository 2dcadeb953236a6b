#pragma once
// One device's step time as a function of its work: time = fixed + per_unit * work.
//
// Fitted by weighted least squares over a sliding window of recent steps, newer steps weighing more
// (exponential forgetting), with a ridge toward the anchor: the last model fitted from a window
// whose work varied enough to tell fixed from per-unit cost (or the prior). Work barely changes
// from step to step, so the data alone usually cannot split the time; the ridge keeps the anchor's
// split until the work varies enough to tell, while the prediction at the work we actually ran
// always follows the measurements.

#include <cstddef>
#include <deque>
#include <optional>

#include "balance/options.hpp"

namespace clsph::balance {

class TimeModel {
 public:
  explicit TimeModel(ModelOptions options = {});

  // Seed the model (a calibration run, or a guess). Without a prior the first sample gives a
  // proportional model (fixed = 0), which is the "last step predicts the next" rule.
  void set_prior(double fixed_seconds, double seconds_per_unit);

  // Add one step's measurement and refit. Samples with no work or no time carry no information
  // about the slope or the level and are ignored (an idle device keeps its last model).
  void observe(double work, double seconds);

  bool ready() const { return ready_; }
  double predict(double work) const { return fixed_ + per_unit_ * work; }
  double fixed() const { return fixed_; }
  double per_unit() const { return per_unit_; }

  std::size_t samples() const { return window_.size(); }
  // Relative standard error of a prediction near the window's work: the weighted RMS of the
  // window's relative residuals over the square root of its effective sample count. Unknown (an
  // empty optional) below ModelOptions::noise_min_samples samples.
  std::optional<double> prediction_error() const { return prediction_error_; }
  // How many times the model saw the device change speed and restarted its window.
  std::size_t speed_changes() const { return speed_changes_; }

 private:
  struct Sample {
    double work;
    double seconds;
  };

  // Relative error of the current model on this sample, when it is a test of the model: the work
  // lies within what the window has already seen. Far outside it, a miss may just mean the
  // fixed/per-unit split was wrong, which the refit will learn; that is not a speed change.
  std::optional<double> surprise(const Sample& sample) const;
  void refit();
  // Share of the time that scales with work, at this work, according to the anchor.
  double anchor_share(double work) const;

  ModelOptions options_;
  std::deque<Sample> window_;      // oldest first
  std::optional<Sample> suspect_;  // a lone surprising sample: a hiccup unless the next agrees
  struct Anchor {
    double fixed;
    double per_unit;
  };
  std::optional<Anchor> anchor_;  // last well-determined model, or the prior
  double fixed_ = 0.0;
  double per_unit_ = 0.0;
  bool ready_ = false;
  std::optional<double> prediction_error_;
  std::size_t speed_changes_ = 0;
};

}  // namespace clsph::balance
