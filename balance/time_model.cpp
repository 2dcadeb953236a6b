#include "balance/time_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace clsph::balance {

namespace {

// How far outside the window's work range a sample may lie and still test the model.
constexpr double seen_work_margin = 0.1;

bool usable(double work, double seconds) {
  return std::isfinite(work) && std::isfinite(seconds) && work > 0.0 && seconds > 0.0;
}

}  // namespace

TimeModel::TimeModel(ModelOptions options) : options_(options) {
  if (options_.window == 0) throw std::invalid_argument("balance: model window must be >= 1");
  if (!(options_.forgetting > 0.0 && options_.forgetting <= 1.0))
    throw std::invalid_argument("balance: model forgetting must be in (0, 1]");
}

void TimeModel::set_prior(double fixed_seconds, double seconds_per_unit) {
  if (!(fixed_seconds >= 0.0) || !(seconds_per_unit > 0.0))
    throw std::invalid_argument("balance: prior needs fixed >= 0 and per-unit > 0");
  fixed_ = fixed_seconds;
  per_unit_ = seconds_per_unit;
  anchor_ = Anchor{fixed_seconds, seconds_per_unit};
  ready_ = true;
}

std::optional<double> TimeModel::surprise(const Sample& sample) const {
  if (!ready_ || window_.empty()) return std::nullopt;
  auto [lo, hi] = std::minmax_element(window_.begin(), window_.end(),
                                      [](const Sample& a, const Sample& b) { return a.work < b.work; });
  if (sample.work < lo->work * (1.0 - seen_work_margin) ||
      sample.work > hi->work * (1.0 + seen_work_margin)) {
    // Outside what the window has seen a miss may be a wrong fixed/per-unit split, which the refit
    // learns. But no split makes the time change by more than the work does: from the nearest seen
    // sample, time scales between 1 (all fixed) and work / seen work (all per-unit). A sample
    // outside that range (widened by the threshold) is a surprise here too, so a first-step
    // hiccup cannot become the model that idles a device.
    const Sample& near = sample.work < lo->work ? *lo : *hi;
    const double ratio = sample.work / near.work;
    const double low = near.seconds * std::min(1.0, ratio) * (1.0 - options_.change_threshold);
    const double high = near.seconds * std::max(1.0, ratio) * (1.0 + options_.change_threshold);
    if (sample.seconds >= low && sample.seconds <= high) return std::nullopt;
    return sample.seconds / predict(sample.work) - 1.0;
  }
  const double error = sample.seconds / predict(sample.work) - 1.0;
  if (std::abs(error) <= options_.change_threshold) return std::nullopt;
  return error;
}

void TimeModel::observe(double work, double seconds) {
  if (!usable(work, seconds)) return;
  const Sample sample{work, seconds};

  if (const auto error = surprise(sample)) {
    const bool confirmed =
        suspect_ && (suspect_->seconds / predict(suspect_->work) - 1.0) * *error > 0.0;
    if (!confirmed) {
      // One odd step (a hiccup, a first-touch page fault) must not move every cut: hold it aside.
      suspect_ = sample;
      return;
    }
    // Two misses the same way: the device changed speed. What it did before no longer predicts
    // it; restart the window from the two new samples. The ridge keeps the old fixed/per-unit
    // split, rescaled to the new level, until the work varies enough to refit it.
    window_.clear();
    window_.push_back(*suspect_);
    ++speed_changes_;
  }
  suspect_.reset();
  window_.push_back(sample);
  while (window_.size() > options_.window) window_.pop_front();
  refit();
}

void TimeModel::refit() {
  // Weighted sums over the window, newest weight 1.
  const std::size_t n = window_.size();
  std::vector<double> weight(n);
  double total = 0.0, mean_work = 0.0, mean_seconds = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    weight[i] = std::pow(options_.forgetting, static_cast<double>(n - 1 - i));
    total += weight[i];
    mean_work += weight[i] * window_[i].work;
    mean_seconds += weight[i] * window_[i].seconds;
  }
  mean_work /= total;
  mean_seconds /= total;

  // Centred, dimensionless regressor x = work / mean_work - 1, so that the parameters are
  //   level = time at the mean work   (well determined by any data)
  //   slope = per_unit * mean_work    (determined only by variation in work)
  // and the ridge can act on the slope alone. Both are in seconds, so the system is well scaled
  // whatever the units of work. The ridge pulls the slope toward the fixed/per-unit split of the
  // anchor (the last well-determined model, or the prior), rescaled to the measured level.
  const Eigen::Vector2d prior(mean_seconds, anchor_share(mean_work) * mean_seconds);

  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d row(1.0, window_[i].work / mean_work - 1.0);
    normal += weight[i] * row * row.transpose();
    rhs += weight[i] * window_[i].seconds * row;
  }
  // The level gets a negligible ridge (only to keep the matrix definite); the slope the real one.
  const Eigen::Vector2d ridge(1e-9 * total, options_.ridge * total);
  // Is the work spread in the window worth at least as much as the prior? normal(1, 1) is the
  // weighted sum of x^2, i.e. total * relative variance of the work.
  const bool identifiable = normal(1, 1) >= ridge(1);
  normal += ridge.asDiagonal();
  rhs += ridge.cwiseProduct(prior);
  const Eigen::Vector2d fit = normal.ldlt().solve(rhs);

  const double level = std::max(fit(0), 1e-12);
  // Physical limits: no negative fixed cost, and work is never free.
  const double slope = std::clamp(fit(1), options_.min_per_unit_share * level, level);
  per_unit_ = slope / mean_work;
  fixed_ = level - slope;
  ready_ = true;
  // Only a window that could tell fixed from per-unit cost moves the anchor. Re-anchoring on
  // every step would let jitter, fitted again and again through overlapping windows, walk the
  // split anywhere while the work stands still.
  if (identifiable) anchor_ = Anchor{fixed_, per_unit_};

  // How well the refitted model explains the window: relative residuals, weighted as in the fit,
  // their RMS scaled by 1/sqrt(effective samples) (exponential weights: (sum w)^2 / sum w^2).
  // Two parameters were fitted, so the residuals understate the noise by about n / (n - 2).
  double squares = 0.0, weight2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = window_[i].seconds / predict(window_[i].work) - 1.0;
    squares += weight[i] * r * r;
    weight2 += weight[i] * weight[i];
  }
  const double effective = total * total / weight2;
  prediction_error_.reset();
  if (n >= options_.noise_min_samples && effective > 2.0)
    prediction_error_ = std::sqrt(squares / total * effective / (effective - 2.0)) / std::sqrt(effective);
}

double TimeModel::anchor_share(double work) const {
  if (!anchor_) return 1.0;  // no prior: proportional, the "last step predicts the next" rule
  const double per_unit_part = anchor_->per_unit * work;
  return per_unit_part / (anchor_->fixed + per_unit_part);
}

}  // namespace clsph::balance
