#pragma once
// Devices whose step time is a known function of their work, plus jitter: they drive the balancer
// in the unit tests and in experiments without any real device. Each device takes
//   true time = fixed + per_unit * work   (0 when its slab is empty)
// and reports it multiplied by (1 + u), u uniform in [-noise, +noise].

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "balance/balance_log.hpp"
#include "balance/balancer.hpp"
#include "balance/cut_search.hpp"
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

  // The true costs, as the balancer would see them with perfect models: the oracle's input.
  std::vector<SlabCost> true_costs() const;

  std::size_t size() const { return devices_.size(); }
  SyntheticDevice& device(std::size_t d) { return devices_.at(d); }
  const SyntheticDevice& device(std::size_t d) const { return devices_.at(d); }

 private:
  std::vector<SyntheticDevice> devices_;
  double noise_;
  std::mt19937_64 random_;
};

// The balancer driving synthetic devices, step after step, as the host would: run with the cuts,
// report, take the new cuts. The profile may be changed between steps.
struct ClosedLoop {
  ClosedLoop(SyntheticDevices devices_, ColumnProfile profile_, Options options);

  Decision step();
  // Over the current cuts, without noise: what the balancer is judged on.
  double true_imbalance() const { return imbalance(devices.true_seconds(cuts, profile)); }
  double true_makespan() const;
  // The smallest makespan any placement could reach with perfect models (min_columns respected).
  double oracle_makespan() const;

  SyntheticDevices devices;
  ColumnProfile profile;
  Balancer balancer;
  std::vector<std::size_t> cuts;
  std::vector<DeviceSample> last_samples;
};

// The work of the whole domain.
double total_work(const ColumnProfile& profile);

// Devices whose per-unit costs step geometrically from `fastest_per_unit` to `ratio` times it.
// All share one fixed cost (launch and synchronisation overhead does not scale with a device's
// throughput): `fixed_share` of the fastest device's time at an equal share of `total_work`.
std::vector<SyntheticDevice> speed_ladder(std::size_t devices, double ratio, double fastest_per_unit,
                                          double fixed_share, double total_work);

// A dam break seen along the split axis: boundary particles on the floor of every column and in
// the two end walls, fluid in [0, front) whose height falls toward the front. The same fluid
// spreads as the front advances, so every column's work changes with it.
ColumnProfile dam_break_profile(std::size_t columns, std::size_t front,
                                std::size_t fluid_particles = 200000);

// A seed for a randomised test: CLSPH_BALANCE_SEED from the environment when set (to replay a
// failure), otherwise a fresh one. Tests print it.
std::uint64_t test_seed();

}  // namespace clsph::balance
