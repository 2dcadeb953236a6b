#include "balance/balancer.hpp"

#include <algorithm>
#include <stdexcept>

namespace clsph::balance {

std::string_view to_string(Reason reason) {
  switch (reason) {
    case Reason::moved: return "moved";
    case Reason::repaired: return "repaired";
    case Reason::below_threshold: return "below_threshold";
    case Reason::no_model_yet: return "no_model_yet";
    case Reason::fixed_by_mode: return "fixed_by_mode";
    case Reason::infeasible: return "infeasible";
  }
  return "unknown";
}

Balancer::Balancer(std::size_t devices, std::size_t columns, Options options)
    : columns_(columns), options_(options), models_(devices, TimeModel(options.model)),
      capacity_(devices, 0), cuts_(equal_width_cuts(devices, columns)), calibrated_(devices, false) {}

void Balancer::check_profile(const ColumnProfile& profile) const {
  if (profile.work.size() != columns_ || profile.particles.size() != columns_)
    throw std::invalid_argument("balance: column profile does not match the column count");
}

std::vector<std::size_t> Balancer::initial_cuts(const ColumnProfile& profile,
                                                const std::vector<std::size_t>& capacity_particles) {
  check_profile(profile);
  if (!capacity_particles.empty()) {
    if (capacity_particles.size() != models_.size())
      throw std::invalid_argument("balance: one capacity per device");
    capacity_ = capacity_particles;
  }
  cuts_ = equal_width_cuts(models_.size(), columns_);
  if (options_.mode == Mode::off) return cuts_;

  // Before any measurement, calibrated models where every device has one; otherwise every device
  // is assumed equally fast: equal work (and nobody idles on a guess).
  bool all_calibrated = true;
  for (bool c : calibrated_) all_calibrated = all_calibrated && c;
  std::vector<SlabCost> costs(models_.size());
  if (all_calibrated) {
    costs = slab_costs();
  } else {
    for (std::size_t d = 0; d < costs.size(); ++d) costs[d] = {0.0, 1.0, capacity_[d], false};
  }
  const Plan plan = place_cuts(costs, ColumnSums(profile), options_.min_columns, cuts_);
  if (plan.feasible) cuts_ = plan.cuts;
  idle_empty_slabs(cuts_, profile);
  return cuts_;
}

void Balancer::idle_empty_slabs(std::vector<std::size_t>& cuts, const ColumnProfile& profile) const {
  // A slab without particles costs its device a step's overhead and a halo for nothing (its model
  // predicts 0 s for 0 work, so the cut search is indifferent to it): its columns go to a
  // neighbour, which gains no work. Not a timing decision, so no evidence is needed.
  if (!options_.allow_idle || options_.mode == Mode::off) return;
  const std::size_t devices = cuts.size() - 1;
  auto particles = [&](std::size_t d) {
    std::size_t n = 0;
    for (std::size_t c = cuts[d]; c < cuts[d + 1]; ++c) n += profile.particles[c];
    return n;
  };
  std::size_t busy = 0;
  for (std::size_t d = 0; d < devices; ++d) busy += particles(d) > 0;
  if (busy == 0) return;
  for (std::size_t round = 0; round < devices; ++round) {
    bool changed = false;
    for (std::size_t d = 0; d < devices; ++d) {
      if (cuts[d] == cuts[d + 1] || particles(d) > 0) continue;
      if (d + 1 < devices)
        cuts[d + 1] = cuts[d];  // to the next device
      else
        cuts[d] = cuts[d + 1];  // the last one's columns to the one before
      changed = true;
    }
    if (!changed) break;
  }
}

void Balancer::calibrate(std::size_t device, double fixed_seconds, double seconds_per_unit) {
  models_.at(device).set_prior(fixed_seconds, seconds_per_unit);
  calibrated_.at(device) = true;
}

double Balancer::gain_threshold() const {
  // The full threshold until every device holding columns knows how well its model predicts.
  double worst = 0.0;
  for (std::size_t d = 0; d < models_.size(); ++d) {
    if (cuts_[d + 1] <= cuts_[d]) continue;  // idle: not measured, its error is not known
    const auto error = models_[d].prediction_error();
    if (!error) return options_.gain_threshold;
    worst = std::max(worst, *error);
  }
  const double lo = std::min(options_.min_gain_threshold, options_.gain_threshold);
  return std::clamp(options_.threshold_standard_errors * worst, lo, options_.gain_threshold);
}

std::vector<SlabCost> Balancer::slab_costs() const {
  double fixed_sum = 0.0, per_unit_sum = 0.0;
  std::size_t known = 0;
  for (const TimeModel& model : models_)
    if (model.ready()) {
      fixed_sum += model.fixed();
      per_unit_sum += model.per_unit();
      ++known;
    }
  std::vector<SlabCost> costs(models_.size());
  for (std::size_t d = 0; d < models_.size(); ++d) {
    const TimeModel& model = models_[d];
    costs[d].capacity_particles = capacity_[d];
    costs[d].may_idle = options_.allow_idle && (calibrated_[d] || model.samples() >= options_.idle_min_samples);
    costs[d].fixed_seconds = model.ready() ? model.fixed() : fixed_sum / static_cast<double>(known);
    costs[d].seconds_per_unit =
        model.ready() ? model.per_unit() : per_unit_sum / static_cast<double>(known);
  }
  return costs;
}

std::vector<CutWindow> Balancer::movement_windows() const {
  const std::size_t reach = options_.max_move_columns;
  std::vector<CutWindow> windows(cuts_.size());
  for (std::size_t k = 0; k < cuts_.size(); ++k)
    windows[k] = {cuts_[k] > reach ? cuts_[k] - reach : 0, std::min(columns_, cuts_[k] + reach)};
  return windows;
}

Decision Balancer::step(const std::vector<DeviceSample>& samples, const ColumnProfile& profile) {
  check_profile(profile);
  if (samples.size() != models_.size())
    throw std::invalid_argument("balance: one sample per device");
  for (std::size_t d = 0; d < models_.size(); ++d) {
    models_[d].observe(samples[d].work, samples[d].compute_seconds);
    capacity_[d] = samples[d].capacity_particles;
  }

  Decision decision;
  decision.cuts = cuts_;
  const bool any_model =
      std::any_of(models_.begin(), models_.end(), [](const TimeModel& m) { return m.ready(); });
  if (!any_model) {
    decision.predicted_seconds.assign(models_.size(), 0.0);
    return decision;
  }

  const ColumnSums columns(profile);
  const std::vector<SlabCost> costs = slab_costs();
  auto finish = [&](Reason reason) {
    idle_empty_slabs(decision.cuts, profile);
    decision.reason = reason;
    decision.moved = decision.cuts != cuts_;
    cuts_ = decision.cuts;
    decision.predicted_seconds = predicted_seconds(costs, columns, cuts_);
    decision.predicted_max =
        *std::max_element(decision.predicted_seconds.begin(), decision.predicted_seconds.end());
    return decision;
  };
  if (options_.mode != Mode::dynamic) return finish(Reason::fixed_by_mode);

  const std::vector<double> now = predicted_seconds(costs, columns, cuts_);
  const double now_max = *std::max_element(now.begin(), now.end());
  const Plan best = place_cuts(costs, columns, options_.min_columns, cuts_);
  if (!best.feasible) return finish(Reason::infeasible);
  // The gain counts the step time first, but also the imbalance: on unequal devices a slow device
  // can idle for a fifth of the step while the step time is within 2 % of the best (a 1:10 pair),
  // and equal predicted times are what the balancer promises.
  const double time_gain = now_max > 0.0 ? (now_max - best.makespan) / now_max : 0.0;
  const double now_imbalance = imbalance(now);
  const double balance_gain =
      (now_imbalance - imbalance(predicted_seconds(costs, columns, best.cuts))) / now_imbalance;
  decision.predicted_gain = std::max(time_gain, balance_gain);

  const bool safe = respects_guard_rails(costs, columns, options_.min_columns, cuts_);
  decision.gain_threshold = gain_threshold();
  if (safe && decision.predicted_gain < decision.gain_threshold)
    return finish(Reason::below_threshold);

  // Step toward the best plan within the movement bound: the best cuts reachable this step,
  // preferring those closest to the full target so that later steps keep converging on it.
  Plan bounded;
  if (options_.max_move_columns > 0)
    bounded = place_cuts(costs, columns, options_.min_columns, best.cuts, movement_windows());
  // Unbounded only when no bounded step can restore the guard rails: memory comes first.
  decision.cuts = bounded.feasible ? bounded.cuts : best.cuts;
  if (decision.cuts == cuts_) return finish(Reason::below_threshold);
  return finish(safe ? Reason::moved : Reason::repaired);
}

}  // namespace clsph::balance
