// Cut placement against brute force: on small instances every placement is enumerated, and the
// search must find the smallest largest-time with every guard rail kept.

#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <random>

#include "balance/cut_search.hpp"
#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

namespace {

ColumnProfile uniform_profile(std::size_t columns, double work, std::size_t particles) {
  return {std::vector<double>(columns, work), std::vector<std::size_t>(columns, particles), {}};
}

// Smallest makespan over every placement (cut vectors enumerated recursively).
double brute_force_makespan(const std::vector<SlabCost>& devices, const ColumnSums& columns,
                            std::size_t min_columns, const std::vector<CutWindow>& windows) {
  const std::size_t count = devices.size(), n = columns.columns();
  std::vector<std::size_t> cuts(count + 1, 0);
  cuts[count] = n;
  double best = std::numeric_limits<double>::infinity();
  std::function<void(std::size_t)> place = [&](std::size_t k) {
    if (k == count) {
      if (!respects_guard_rails(devices, columns, min_columns, cuts)) return;
      const std::vector<double> s = predicted_seconds(devices, columns, cuts);
      best = std::min(best, *std::max_element(s.begin(), s.end()));
      return;
    }
    for (std::size_t c = cuts[k - 1]; c <= n; ++c) {
      if (!windows.empty() && (c < windows[k].lo || c > windows[k].hi)) continue;
      if (!columns.cut_allowed(c)) continue;
      cuts[k] = c;
      place(k + 1);
    }
  };
  place(1);
  return best;
}

}  // namespace

TEST_CASE("cut search: equal devices on a uniform profile get equal slabs") {
  const ColumnProfile profile = uniform_profile(12, 1.0, 10);
  const std::vector<SlabCost> devices(4, SlabCost{0.5, 1.0, 0});
  const Plan plan = place_cuts(devices, ColumnSums(profile), 1, equal_width_cuts(4, 12));
  REQUIRE(plan.feasible);
  CHECK(plan.cuts == std::vector<std::size_t>{0, 3, 6, 9, 12});
  CHECK(plan.makespan == doctest::Approx(3.5));
}

TEST_CASE("cut search: slabs follow the work, not the width") {
  // Heavy first half (work 3 per column), light second half (work 1), 48 in all: two equal
  // devices meet at 24, after 8 heavy columns, not at the middle column 12.
  ColumnProfile profile = uniform_profile(24, 1.0, 1);
  for (std::size_t c = 0; c < 12; ++c) profile.work[c] = 3.0;
  const std::vector<SlabCost> devices(2, SlabCost{0.0, 1.0, 0});
  const Plan plan = place_cuts(devices, ColumnSums(profile), 1, equal_width_cuts(2, 24));
  REQUIRE(plan.feasible);
  CHECK(plan.cuts == std::vector<std::size_t>{0, 8, 24});
}

TEST_CASE("cut search: matches brute force on random small instances") {
  const std::uint64_t seed = test_seed();
  MESSAGE("seed " << seed << " (replay with CLSPH_BALANCE_SEED)");
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  for (int instance = 0; instance < 300; ++instance) {
    const std::size_t count = 1 + random() % 4, n = 4 + random() % 9;
    ColumnProfile profile;
    for (std::size_t c = 0; c < n; ++c) {
      profile.work.push_back(unit(random) < 0.15 ? 0.0 : 0.1 + 3.0 * unit(random));
      profile.particles.push_back(random() % 20);
    }
    std::vector<SlabCost> devices(count);
    for (SlabCost& d : devices) {
      // Some devices are very slow or carry a large fixed cost, so that leaving them idle wins.
      d.fixed_seconds = unit(random) < 0.2 ? 20.0 * unit(random) : unit(random);
      d.seconds_per_unit = unit(random) < 0.2 ? 10.0 * unit(random) : 0.1 + unit(random);
      d.capacity_particles = unit(random) < 0.3 ? 5 + random() % 60 : 0;
    }
    const std::size_t min_columns = 1 + random() % 3;
    // Some instances forbid cuts at some columns (the host's mDBC halos: ColumnProfile::cut_allowed).
    if (unit(random) < 0.3) {
      profile.cut_allowed.assign(n + 1, 1);
      for (std::size_t c = 1; c < n; ++c) profile.cut_allowed[c] = unit(random) < 0.4 ? 0 : 1;
    }
    std::vector<CutWindow> windows;
    const std::vector<std::size_t> start = equal_width_cuts(count, n);
    if (unit(random) < 0.3) {
      const std::size_t reach = 1 + random() % 3;
      for (std::size_t c : start) windows.push_back({c > reach ? c - reach : 0, std::min(n, c + reach)});
    }

    const ColumnSums columns(profile);
    const double expected = brute_force_makespan(devices, columns, min_columns, windows);
    const Plan plan = place_cuts(devices, columns, min_columns, start, windows);
    INFO("instance " << instance << ": " << count << " devices, " << n << " columns, min "
                     << min_columns << (windows.empty() ? "" : ", windowed")
                     << (profile.cut_allowed.empty() ? "" : ", forbidden cuts"));
    REQUIRE(plan.feasible == (expected < std::numeric_limits<double>::infinity()));
    if (!plan.feasible) continue;
    REQUIRE(respects_guard_rails(devices, columns, min_columns, plan.cuts));
    for (std::size_t c : plan.cuts) REQUIRE(columns.cut_allowed(c));
    for (std::size_t k = 0; k < windows.size(); ++k) {
      REQUIRE(plan.cuts[k] >= windows[k].lo);
      REQUIRE(plan.cuts[k] <= windows[k].hi);
    }
    REQUIRE(plan.makespan == doctest::Approx(expected).epsilon(1e-7));
  }
}

TEST_CASE("cut search: among equally good plans, the cuts nearest the preferred ones") {
  // Columns 4..7 hold no work: the cut between two equal devices may sit anywhere there.
  ColumnProfile profile = uniform_profile(12, 1.0, 1);
  for (std::size_t c = 4; c < 8; ++c) profile.work[c] = 0.0;
  const std::vector<SlabCost> devices(2, SlabCost{0.0, 1.0, 0});
  const ColumnSums columns(profile);
  CHECK(place_cuts(devices, columns, 1, {0, 5, 12}).cuts[1] == 5);
  CHECK(place_cuts(devices, columns, 1, {0, 7, 12}).cuts[1] == 7);
  CHECK(place_cuts(devices, columns, 1, {0, 11, 12}).cuts[1] == 8);
}

TEST_CASE("cut search: infeasible when the particles do not fit") {
  const ColumnProfile profile = uniform_profile(10, 1.0, 10);  // 100 particles
  const std::vector<SlabCost> devices(2, SlabCost{0.0, 1.0, 40});
  CHECK_FALSE(place_cuts(devices, ColumnSums(profile), 1, equal_width_cuts(2, 10)).feasible);
}
