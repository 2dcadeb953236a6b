// A dam-break front advancing along the split axis: every column's work changes as the fluid
// spreads, and the cuts must follow it without letting the imbalance build up.
//
// Asserted on the noise-free times of the chosen cuts (see convergence_test.cpp for why): after
// 20 steps of initial convergence, the imbalance stays under 1.10 at every step.

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

TEST_CASE("drift: a dam-break front moving one column every 3 steps") {
  const std::uint64_t seed = test_seed();
  MESSAGE("seed " << seed << " (replay with CLSPH_BALANCE_SEED)");
  std::mt19937_64 random(seed);

  constexpr std::size_t columns = 400, steps_per_column = 3;
  for (std::size_t devices : {2, 4, 8})
    for (double ratio : {1.0, 3.0}) {
      std::size_t front = columns / 4;
      ColumnProfile profile = dam_break_profile(columns, front);
      const double total = std::accumulate(profile.work.begin(), profile.work.end(), 0.0);
      std::vector<SyntheticDevice> ladder = speed_ladder(devices, ratio, 1e-8, 0.2, total);
      std::shuffle(ladder.begin(), ladder.end(), random);
      ClosedLoop loop(SyntheticDevices(ladder, 0.05, random()), profile, Options{});

      double worst = 1.0;
      std::size_t moves = 0;
      for (std::size_t step = 0; step < 200; ++step) {
        if (step % steps_per_column == 0) loop.profile = dam_break_profile(columns, ++front);
        moves += loop.step().moved ? 1 : 0;
        if (step >= 20) worst = std::max(worst, loop.true_imbalance());
      }
      INFO(devices << " devices, ratio 1:" << ratio << ": worst imbalance " << worst << ", "
                   << moves << " moves in 200 steps, front at column " << front);
      CHECK(worst <= 1.10);
    }
}
