// Steady state: with nothing changing but the jitter, cuts must not wander back and forth.
// A reversal is a cut moving opposite to its previous move; each cut may reverse at most once in
// 50 steps (a jitter-driven move that is later undone), never oscillate.

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

TEST_CASE("steady state: no cut moves back and forth") {
  const std::uint64_t seed = test_seed();
  MESSAGE("seed " << seed << " (replay with CLSPH_BALANCE_SEED)");
  std::mt19937_64 random(seed);

  constexpr std::size_t columns = 400;
  // Noisy devices keep the full gain threshold; precise ones (0.1 % jitter) get a much lower one,
  // which must not make cuts oscillate either.
  for (double noise : {0.05, 0.001})
  for (std::size_t devices : {2, 4, 8})
    for (double ratio : {1.0, 3.0, 10.0}) {
      const ColumnProfile profile = dam_break_profile(columns, columns / 2);
      const double total = std::accumulate(profile.work.begin(), profile.work.end(), 0.0);
      std::vector<SyntheticDevice> ladder = speed_ladder(devices, ratio, 1e-8, 0.2, total);
      std::shuffle(ladder.begin(), ladder.end(), random);
      ClosedLoop loop(SyntheticDevices(ladder, noise, random()), profile, Options{});
      for (int step = 0; step < 30; ++step) loop.step();

      std::vector<int> last_direction(devices + 1, 0);
      std::vector<int> reversals(devices + 1, 0);
      std::size_t moves = 0;
      for (int step = 0; step < 50; ++step) {
        const std::vector<std::size_t> before = loop.cuts;
        loop.step();
        for (std::size_t k = 1; k < devices; ++k) {
          const int direction = (loop.cuts[k] > before[k]) - (loop.cuts[k] < before[k]);
          if (direction == 0) continue;
          ++moves;
          if (last_direction[k] == -direction) ++reversals[k];
          last_direction[k] = direction;
        }
      }
      INFO("jitter +-" << noise << ", " << devices << " devices, ratio 1:" << ratio << ": " << moves << " cut moves, at most "
                   << *std::max_element(reversals.begin(), reversals.end())
                   << " reversals of one cut in 50 steps");
      CHECK(*std::max_element(reversals.begin(), reversals.end()) <= 1);
    }
}
