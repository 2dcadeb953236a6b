// The per-step CSV log: one header, one row per step, the prediction for a step on the same row
// as its measurement.

#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <vector>

#include "balance/balance_log.hpp"
#include "balance/synthetic_devices.hpp"

using namespace clsph::balance;

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

TEST_CASE("imbalance: max/mean over the busy devices") {
  CHECK(imbalance({1.0, 1.0, 1.0}) == 1.0);
  CHECK(imbalance({2.0, 1.0}) == doctest::Approx(2.0 / 1.5));
  CHECK(imbalance({2.0, 1.0, 0.0}) == doctest::Approx(2.0 / 1.5));  // an idle device is not late
  CHECK(imbalance({}) == 1.0);
}

TEST_CASE("balance log: header, rows, and predictions next to their measurements") {
  const ColumnProfile profile = dam_break_profile(100, 50);
  SyntheticDevices devices({{1e-4, 1e-8, 0}, {1e-4, 3e-8, 0}}, 0.0, 1);
  Balancer balancer(2, 100);
  std::vector<std::size_t> cuts = balancer.initial_cuts(profile);

  std::ostringstream out;
  BalanceLog log(out, 2);
  std::vector<Decision> decisions;
  for (std::size_t step = 0; step < 3; ++step) {
    const std::vector<DeviceSample> samples = devices.run_step(cuts, profile);
    decisions.push_back(balancer.step(samples, profile));
    log.write(step, samples, decisions.back());
    cuts = decisions.back().cuts;
  }

  std::istringstream in(out.str());
  std::string line;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) rows.push_back(split(line));
  REQUIRE(rows.size() == 4);

  const std::vector<std::string>& header = rows[0];
  const std::size_t width = 6 + 5 * 2 + 3;
  REQUIRE(header.size() == width);
  CHECK(header[0] == "step");
  CHECK(header[1] == "imbalance");
  CHECK(header[5] == "reason");
  CHECK(header[6] == "d0_measured_s");
  CHECK(header[7] == "d0_predicted_s");
  CHECK(header[8] == "d0_next_s");
  CHECK(header[9] == "d0_work");
  CHECK(header[10] == "d0_particles");
  CHECK(header[16] == "cut0");
  CHECK(header[18] == "cut2");

  for (std::size_t r = 1; r < rows.size(); ++r) REQUIRE(rows[r].size() == width);
  CHECK(rows[1][0] == "0");
  CHECK(rows[1][7].empty());  // nothing was predicted for the first step
  // Row 2's predicted time for device 0 is what row 1 announced as its next time.
  CHECK(std::stod(rows[2][7]) == doctest::Approx(decisions[0].predicted_seconds[0]));
  CHECK(std::stod(rows[2][8]) == doctest::Approx(decisions[1].predicted_seconds[0]));
  CHECK(rows[1][5] == std::string(to_string(decisions[0].reason)));
  CHECK(std::stoul(rows[3][17]) == decisions[2].cuts[1]);
  CHECK(std::stod(rows[1][1]) >= 1.0);
}
