#pragma once
// Devices whose step time is a known function of their work, plus jitter: they drive the balancer
// in the unit tests and in experiments without any real device. Each device takes
//   true time = fixed + per_unit * work   (0 when its slab is empty)
// and reports it multiplied by (1 + u), u uniform in [-noise, +noise].

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "balance/inputs.hpp"

namespace clsph::balance {

struct SyntheticDevice {
  double fixed_seconds = 0.0;
  double seconds_per_unit = 0.0;
  std::size_t capacity_particles = 0;  // reported in every sample; 0 = unlimited
};

class SyntheticDevices {
 public:
  SyntheticDevices(std::vector<SyntheticDevice> devices, double noise, std::uint64_t seed);

  // Noise-free time of each device for the slabs given by cuts.
  std::vector<double> true_seconds(const std::vector<std::size_t>& cuts,
                                   const ColumnProfile& profile) const;
  // One step as the devices would report it.
  std::vector<DeviceSample> run_step(const std::vector<std::size_t>& cuts,
                                     const ColumnProfile& profile);

  std::size_t size() const { return devices_.size(); }
  SyntheticDevice& device(std::size_t d) { return devices_.at(d); }
  const SyntheticDevice& device(std::size_t d) const { return devices_.at(d); }

 private:
  std::vector<SyntheticDevice> devices_;
  double noise_;
  std::mt19937_64 random_;
};

// A seed for a randomised test: CLSPH_BALANCE_SEED from the environment when set (to replay a
// failure), otherwise a fresh one. Tests print it.
std::uint64_t test_seed();

}  // namespace clsph::balance
