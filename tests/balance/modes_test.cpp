// Modes (dynamic, static, off), the reasons a decision gives, and inputs the balancer refuses.

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

namespace {

constexpr std::size_t columns = 200;

ColumnProfile test_profile() { return dam_break_profile(columns, columns / 2); }

// Two devices, the second three times slower: equal work is far from balanced.
SyntheticDevices unequal_pair(const ColumnProfile& profile) {
  const double total = std::accumulate(profile.work.begin(), profile.work.end(), 0.0);
  return SyntheticDevices(speed_ladder(2, 3.0, 1e-8, 0.2, total), 0.0, 1);
}

Options with_mode(Mode mode) {
  Options options;
  options.mode = mode;
  return options;
}

}  // namespace

TEST_CASE("modes: names round-trip") {
  for (Mode mode : {Mode::dynamic, Mode::static_, Mode::off})
    CHECK(mode_from_string(to_string(mode)) == mode);
  CHECK_FALSE(mode_from_string("sometimes").has_value());
}

TEST_CASE("modes: off cuts equal widths and never moves") {
  const ColumnProfile profile = test_profile();
  ClosedLoop loop(unequal_pair(profile), profile, with_mode(Mode::off));
  CHECK(loop.cuts == std::vector<std::size_t>{0, 100, 200});
  for (int step = 0; step < 5; ++step) {
    const Decision decision = loop.step();
    CHECK(decision.reason == Reason::fixed_by_mode);
    CHECK_FALSE(decision.moved);
    CHECK(decision.predicted_max > 0.0);  // still predicted, for the log
  }
  CHECK(loop.cuts == std::vector<std::size_t>{0, 100, 200});
}

TEST_CASE("modes: static cuts once by work and never moves") {
  const ColumnProfile profile = test_profile();
  ClosedLoop loop(unequal_pair(profile), profile, with_mode(Mode::static_));
  const std::vector<double> work = slab_work(loop.cuts, profile);
  const double heaviest_column = *std::max_element(profile.work.begin(), profile.work.end());
  CHECK(std::abs(work[0] - work[1]) <= heaviest_column);  // equal work, to one column
  CHECK(loop.cuts[1] < 100);  // the fluid is at the front of the axis, so not equal widths
  const std::vector<std::size_t> start = loop.cuts;
  for (int step = 0; step < 5; ++step) CHECK(loop.step().reason == Reason::fixed_by_mode);
  CHECK(loop.cuts == start);
}

TEST_CASE("modes: dynamic moves the cuts toward the faster device") {
  const ColumnProfile profile = test_profile();
  ClosedLoop loop(unequal_pair(profile), profile, Options{});
  const std::vector<std::size_t> start = loop.cuts;
  const Decision decision = loop.step();
  CHECK(decision.reason == Reason::moved);
  CHECK(decision.moved);
  CHECK(decision.predicted_gain > 0.1);
  CHECK(loop.cuts[1] > start[1]);  // device 0 is the faster one
  CHECK(decision.predicted_max ==
        doctest::Approx(*std::max_element(decision.predicted_seconds.begin(),
                                          decision.predicted_seconds.end())));
}

TEST_CASE("reasons: no model yet, and infeasible capacities") {
  const ColumnProfile profile = test_profile();
  Balancer balancer(2, columns);
  const std::vector<std::size_t> start = balancer.initial_cuts(profile);
  // A first step that measured nothing (e.g. timers not ready) leaves the cuts alone.
  Decision decision = balancer.step({DeviceSample{}, DeviceSample{}}, profile);
  CHECK(decision.reason == Reason::no_model_yet);
  CHECK(decision.cuts == start);

  // Neither device can hold even half the particles: nothing fits, the cuts stay, the host hears.
  const std::size_t particles =
      std::accumulate(profile.particles.begin(), profile.particles.end(), std::size_t{0});
  std::vector<DeviceSample> samples = unequal_pair(profile).run_step(start, profile);
  for (DeviceSample& sample : samples) sample.capacity_particles = particles / 3;
  decision = balancer.step(samples, profile);
  CHECK(decision.reason == Reason::infeasible);
  CHECK(decision.cuts == start);
}

TEST_CASE("inputs: mismatched sizes are refused") {
  const ColumnProfile profile = test_profile();
  Balancer balancer(2, columns);
  ColumnProfile short_profile = profile;
  short_profile.work.pop_back();
  short_profile.particles.pop_back();
  CHECK_THROWS_AS(balancer.initial_cuts(short_profile), std::invalid_argument);
  CHECK_THROWS_AS(balancer.step({DeviceSample{}}, profile), std::invalid_argument);
  CHECK_THROWS_AS(balancer.initial_cuts(profile, {1, 2, 3}), std::invalid_argument);
}

TEST_CASE("inputs: column work weighs boundary particles") {
  CHECK(column_work(100, 0) == 100.0);
  CHECK(column_work(100, 50) == doctest::Approx(100.0 + 50.0 * default_boundary_weight));
  CHECK(column_work(0, 10, 1.0) == 10.0);
  CHECK(equal_width_cuts(3, 10) == std::vector<std::size_t>{0, 3, 6, 10});
}
