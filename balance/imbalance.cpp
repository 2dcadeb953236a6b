#include "balance/imbalance.hpp"

#include <algorithm>
#include <cstddef>

namespace clsph::balance {

double imbalance(const std::vector<double>& seconds) {
  double largest = 0.0, sum = 0.0;
  std::size_t busy = 0;
  for (double s : seconds)
    if (s > 0.0) {
      largest = std::max(largest, s);
      sum += s;
      ++busy;
    }
  return busy == 0 ? 1.0 : largest / (sum / static_cast<double>(busy));
}

}  // namespace clsph::balance
