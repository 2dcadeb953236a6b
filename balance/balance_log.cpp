#include "balance/balance_log.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace clsph::balance {

BalanceLog::BalanceLog(std::ostream& out, std::size_t devices) : out_(out), devices_(devices) {}

void BalanceLog::write_header() {
  std::ostringstream row;
  row << "step,imbalance,predicted_max,predicted_gain,moved,reason";
  for (std::size_t d = 0; d < devices_; ++d)
    row << ",d" << d << "_measured_s,d" << d << "_predicted_s,d" << d << "_next_s,d" << d
        << "_work,d" << d << "_particles";
  for (std::size_t k = 0; k <= devices_; ++k) row << ",cut" << k;
  out_ << row.str() << '\n';
  header_written_ = true;
}

void BalanceLog::write(std::size_t step, const std::vector<DeviceSample>& measured,
                       const Decision& decision) {
  if (measured.size() != devices_ || decision.cuts.size() != devices_ + 1)
    throw std::invalid_argument("balance: log row does not match the device count");
  if (!header_written_) write_header();

  std::vector<double> seconds(devices_);
  for (std::size_t d = 0; d < devices_; ++d) seconds[d] = measured[d].compute_seconds;

  // Enough digits to compare predicted and measured times to a fraction of a percent.
  std::ostringstream row;
  row.precision(9);
  row << step << ',' << imbalance(seconds) << ',' << decision.predicted_max << ','
      << decision.predicted_gain << ',' << (decision.moved ? 1 : 0) << ','
      << to_string(decision.reason);
  for (std::size_t d = 0; d < devices_; ++d) {
    row << ',' << measured[d].compute_seconds << ',';
    if (d < predicted_.size()) row << predicted_[d];
    row << ',' << (d < decision.predicted_seconds.size() ? decision.predicted_seconds[d] : 0.0)
        << ',' << measured[d].work << ',' << measured[d].particles;
  }
  for (std::size_t cut : decision.cuts) row << ',' << cut;
  out_ << row.str() << '\n';
  out_.flush();  // a row a step, readable while the run goes on (tail -f)
  predicted_ = decision.predicted_seconds;
}

}  // namespace clsph::balance
