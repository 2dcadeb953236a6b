#include "balance/inputs.hpp"

#include <stdexcept>

namespace clsph::balance {

double column_work(std::size_t fluid, std::size_t boundary, double boundary_weight) {
  return static_cast<double>(fluid) + boundary_weight * static_cast<double>(boundary);
}

namespace {

void check_cuts(const std::vector<std::size_t>& cuts, std::size_t columns) {
  if (cuts.size() < 2 || cuts.front() != 0 || cuts.back() != columns)
    throw std::invalid_argument("balance: cuts must start at 0 and end at the column count");
  for (std::size_t k = 1; k < cuts.size(); ++k)
    if (cuts[k] < cuts[k - 1]) throw std::invalid_argument("balance: cuts must not decrease");
}

}  // namespace

std::vector<double> slab_work(const std::vector<std::size_t>& cuts, const ColumnProfile& profile) {
  check_cuts(cuts, profile.work.size());
  std::vector<double> work(cuts.size() - 1, 0.0);
  for (std::size_t d = 0; d + 1 < cuts.size(); ++d)
    for (std::size_t c = cuts[d]; c < cuts[d + 1]; ++c) work[d] += profile.work[c];
  return work;
}

std::vector<std::size_t> slab_particles(const std::vector<std::size_t>& cuts,
                                        const ColumnProfile& profile) {
  check_cuts(cuts, profile.particles.size());
  std::vector<std::size_t> particles(cuts.size() - 1, 0);
  for (std::size_t d = 0; d + 1 < cuts.size(); ++d)
    for (std::size_t c = cuts[d]; c < cuts[d + 1]; ++c) particles[d] += profile.particles[c];
  return particles;
}

std::vector<std::size_t> equal_width_cuts(std::size_t devices, std::size_t columns) {
  if (devices == 0) throw std::invalid_argument("balance: need at least one device");
  std::vector<std::size_t> cuts(devices + 1);
  for (std::size_t d = 0; d <= devices; ++d) cuts[d] = d * columns / devices;
  return cuts;
}

}  // namespace clsph::balance
