#include "balance/synthetic_devices.hpp"

#include <cstdlib>
#include <string>

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

std::uint64_t test_seed() {
  if (const char* text = std::getenv("CLSPH_BALANCE_SEED")) return std::stoull(text);
  return std::random_device{}();
}

}  // namespace clsph::balance
