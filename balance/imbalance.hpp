#pragma once
// The balance metric used everywhere (log, decisions, tests): max/mean of step times over the
// devices that had work. An idle device is not late, so it does not count toward the mean.

#include <vector>

namespace clsph::balance {

// max/mean over the positive entries; 1 when there are none.
double imbalance(const std::vector<double>& seconds);

}  // namespace clsph::balance
