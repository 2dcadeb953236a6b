#include "balance/synthetic_devices.hpp"

#include <algorithm>
#include <numeric>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

namespace clsph::balance {

SyntheticDevices::SyntheticDevices(std::vector<SyntheticDevice> devices, double noise,
                                   std::uint64_t seed)
    : devices_(std::move(devices)), noise_(noise), random_(seed) {}

std::vector<double> SyntheticDevices::true_seconds(const std::vector<std::size_t>& cuts,
                                                   const ColumnProfile& profile) const {
  const std::vector<double> work = slab_work(cuts, profile);
  std::vector<double> seconds(devices_.size(), 0.0);
  for (std::size_t d = 0; d < devices_.size(); ++d)
    if (cuts[d + 1] > cuts[d])
      seconds[d] = devices_[d].fixed_seconds + devices_[d].seconds_per_unit * work[d];
  return seconds;
}

std::vector<DeviceSample> SyntheticDevices::run_step(const std::vector<std::size_t>& cuts,
                                                     const ColumnProfile& profile) {
  const std::vector<double> seconds = true_seconds(cuts, profile);
  const std::vector<double> work = slab_work(cuts, profile);
  const std::vector<std::size_t> particles = slab_particles(cuts, profile);
  std::uniform_real_distribution<double> jitter(-noise_, noise_);
  std::vector<DeviceSample> samples(devices_.size());
  for (std::size_t d = 0; d < devices_.size(); ++d)
    samples[d] = {seconds[d] * (1.0 + jitter(random_)), work[d], particles[d],
                  devices_[d].capacity_particles};
  return samples;
}

std::vector<SlabCost> SyntheticDevices::true_costs() const {
  std::vector<SlabCost> costs(devices_.size());
  for (std::size_t d = 0; d < devices_.size(); ++d)
    costs[d] = {devices_[d].fixed_seconds, devices_[d].seconds_per_unit,
                devices_[d].capacity_particles};
  return costs;
}

double total_work(const ColumnProfile& profile) {
  return std::accumulate(profile.work.begin(), profile.work.end(), 0.0);
}

ClosedLoop::ClosedLoop(SyntheticDevices devices_, ColumnProfile profile_, Options options)
    : devices(std::move(devices_)), profile(std::move(profile_)),
      balancer(devices.size(), profile.work.size(), options) {
  std::vector<std::size_t> capacities(devices.size());
  for (std::size_t d = 0; d < devices.size(); ++d) capacities[d] = devices.device(d).capacity_particles;
  cuts = balancer.initial_cuts(profile, capacities);
}

Decision ClosedLoop::step() {
  last_samples = devices.run_step(cuts, profile);
  Decision decision = balancer.step(last_samples, profile);
  cuts = decision.cuts;
  return decision;
}

double ClosedLoop::true_makespan() const {
  const std::vector<double> seconds = devices.true_seconds(cuts, profile);
  return *std::max_element(seconds.begin(), seconds.end());
}

double ClosedLoop::oracle_makespan() const {
  const Plan best = place_cuts(devices.true_costs(), ColumnSums(profile),
                               balancer.options().min_columns, cuts);
  return best.feasible ? best.makespan : 0.0;
}

std::vector<SyntheticDevice> speed_ladder(std::size_t devices, double ratio, double fastest_per_unit,
                                          double fixed_share, double total_work) {
  std::vector<SyntheticDevice> ladder(devices);
  const double share = total_work / static_cast<double>(devices);
  // fastest time at an equal share = fixed + fastest_per_unit * share, of which fixed is fixed_share
  const double fixed = fixed_share / (1.0 - fixed_share) * fastest_per_unit * share;
  for (std::size_t d = 0; d < devices; ++d) {
    const double step = devices > 1 ? static_cast<double>(d) / static_cast<double>(devices - 1) : 0;
    ladder[d].seconds_per_unit = fastest_per_unit * std::pow(ratio, step);
    ladder[d].fixed_seconds = fixed;
  }
  return ladder;
}

ColumnProfile dam_break_profile(std::size_t columns, std::size_t front,
                                std::size_t fluid_particles) {
  constexpr std::size_t floor_particles = 30, wall_particles = 600;
  front = std::clamp<std::size_t>(front, 1, columns);
  std::vector<double> height(front);
  double height_sum = 0.0;
  for (std::size_t c = 0; c < front; ++c) {
    const double x = (static_cast<double>(c) + 0.5) / static_cast<double>(front);
    height[c] = 1.0 - 0.8 * x * x;  // the collapsing column: high at the back, thin at the front
    height_sum += height[c];
  }
  ColumnProfile profile{std::vector<double>(columns), std::vector<std::size_t>(columns), {}};
  for (std::size_t c = 0; c < columns; ++c) {
    const std::size_t fluid =
        c < front ? static_cast<std::size_t>(std::lround(static_cast<double>(fluid_particles) *
                                                         height[c] / height_sum))
                  : 0;
    const std::size_t boundary = floor_particles + (c == 0 || c + 1 == columns ? wall_particles : 0);
    profile.work[c] = column_work(fluid, boundary);
    profile.particles[c] = fluid + boundary;
  }
  return profile;
}

std::uint64_t test_seed() {
  if (const char* text = std::getenv("CLSPH_BALANCE_SEED")) return std::stoull(text);
  return std::random_device{}();
}

}  // namespace clsph::balance
