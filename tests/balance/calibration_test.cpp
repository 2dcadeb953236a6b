// The first cut from a calibration run (a GPU next to a CPU must not start with half the work on
// the CPU), and idling only on evidence: a calibration, or a model with enough measured steps.

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>

#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

namespace {

constexpr std::size_t columns = 400;
constexpr double fast_per_unit = 1e-8;

ColumnProfile test_profile() { return dam_break_profile(columns, columns / 2); }

double makespan(const SyntheticDevices& devices, const std::vector<std::size_t>& cuts, const ColumnProfile& profile) {
  const auto s = devices.true_seconds(cuts, profile);
  return *std::max_element(s.begin(), s.end());
}

}  // namespace

TEST_CASE("calibration: the first cut follows the calibrated speeds") {
  const ColumnProfile profile = test_profile();
  // 1 : 30, like a GPU next to a CPU; the calibration is off by +-10 %.
  SyntheticDevices devices(speed_ladder(2, 30.0, fast_per_unit, 0.05, total_work(profile)), 0.0, 1);
  Balancer plain(2, columns, Options{});
  const auto equal_cuts = plain.initial_cuts(profile);
  Balancer calibrated(2, columns, Options{});
  calibrated.calibrate(0, devices.device(0).fixed_seconds * 1.1, devices.device(0).seconds_per_unit * 0.9);
  calibrated.calibrate(1, devices.device(1).fixed_seconds * 0.9, devices.device(1).seconds_per_unit * 1.1);
  const auto cuts = calibrated.initial_cuts(profile);
  const double uncalibrated = makespan(devices, equal_cuts, profile), first = makespan(devices, cuts, profile);
  INFO("equal-work cut " << equal_cuts[1] << ": " << uncalibrated << " s; calibrated cut " << cuts[1] << ": " << first << " s");
  // Equal work puts half the domain on the slow device: ~15x the balanced step.
  CHECK(uncalibrated > 5.0 * first);
  // The fast device alone would take this long; the calibrated first step must beat it.
  const double alone = devices.device(0).fixed_seconds + devices.device(0).seconds_per_unit * total_work(profile);
  CHECK(first < alone);
  CHECK(imbalance(devices.true_seconds(cuts, profile)) <= 1.25);  // 20 % calibration error, column granularity
}

TEST_CASE("calibration: a device too slow for even one column starts idle") {
  const ColumnProfile profile = test_profile();
  auto devs = speed_ladder(2, 1.0, fast_per_unit, 0.2, total_work(profile));
  // The second device's overhead per step alone exceeds the whole domain on the first.
  devs[1].seconds_per_unit *= 500.0;
  devs[1].fixed_seconds = 2.0 * (devs[0].fixed_seconds + devs[0].seconds_per_unit * total_work(profile));
  SyntheticDevices devices(devs, 0.0, 1);
  Balancer b(2, columns, Options{});
  for (std::size_t d = 0; d < 2; ++d) b.calibrate(d, devs[d].fixed_seconds, devs[d].seconds_per_unit);
  const auto cuts = b.initial_cuts(profile);
  INFO("cuts " << cuts[0] << " " << cuts[1] << " " << cuts[2]);
  CHECK(cuts[1] == columns);  // device 1 idle from the start
  // Without idling allowed it keeps min_columns, and the step is slower than the fast device alone.
  Options no_idle;
  no_idle.allow_idle = false;
  Balancer kept(2, columns, no_idle);
  for (std::size_t d = 0; d < 2; ++d) kept.calibrate(d, devs[d].fixed_seconds, devs[d].seconds_per_unit);
  const auto kept_cuts = kept.initial_cuts(profile);
  CHECK(kept_cuts[2] - kept_cuts[1] >= 1);
  CHECK(makespan(devices, kept_cuts, profile) > makespan(devices, cuts, profile));
}

TEST_CASE("calibration: one noisy step does not idle a device") {
  const std::uint64_t seed = test_seed();
  MESSAGE("seed " << seed << " (replay with CLSPH_BALANCE_SEED)");
  const ColumnProfile profile = test_profile();
  SyntheticDevices devices(speed_ladder(3, 1.0, fast_per_unit, 0.2, total_work(profile)), 0.05, seed);
  Balancer b(3, columns, Options{});
  auto cuts = b.initial_cuts(profile);
  for (int step = 0; step < 40; ++step) {
    auto samples = devices.run_step(cuts, profile);
    if (step == 0) samples[1].compute_seconds *= 1000.0;  // a hiccup: page faults, a context switch
    cuts = b.step(samples, profile).cuts;
    INFO("step " << step << ": cuts " << cuts[1] << " " << cuts[2]);
    REQUIRE(cuts[2] > cuts[1]);  // the middle device keeps columns throughout
  }
  CHECK(imbalance(devices.true_seconds(cuts, profile)) <= 1.05);
}

TEST_CASE("calibration: no device is left holding only columns without particles") {
  // Half the domain is empty (the tank beyond the water and its floor): the model predicts 0 s
  // for 0 work, so a slow device's narrowest slab lands there, where it would still pay a step's
  // overhead and a halo. It must be idled instead.
  ColumnProfile profile = test_profile();
  for (std::size_t c = columns / 2; c < columns; ++c) {
    profile.work[c] = 0.0;
    profile.particles[c] = 0;
  }
  for (std::size_t devices : {2u, 3u}) {
    auto devs = speed_ladder(devices, 1.0, fast_per_unit, 0.0, total_work(profile));
    devs.back().seconds_per_unit *= 1000.0;  // a CPU next to GPUs
    Balancer b(devices, columns, Options{});
    for (std::size_t d = 0; d < devices; ++d) b.calibrate(d, devs[d].fixed_seconds, devs[d].seconds_per_unit);
    auto check = [&](const std::vector<std::size_t>& cuts) {
      for (std::size_t d = 0; d < devices; ++d) {
        std::size_t n = 0;
        for (std::size_t c = cuts[d]; c < cuts[d + 1]; ++c) n += profile.particles[c];
        INFO(devices << " devices, device " << d << ": columns [" << cuts[d] << ", " << cuts[d + 1] << ")");
        CHECK((cuts[d] == cuts[d + 1] || n > 0));
      }
      CHECK(cuts.front() == 0);
      CHECK(cuts.back() == columns);
      CHECK(std::is_sorted(cuts.begin(), cuts.end()));
    };
    auto cuts = b.initial_cuts(profile);
    check(cuts);
    SyntheticDevices sim(devs, 0.02, 7);
    for (int step = 0; step < 30; ++step) cuts = b.step(sim.run_step(cuts, profile), profile).cuts;
    check(cuts);
  }
}
