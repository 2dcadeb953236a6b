// Floating bodies through clsph run (issue 32 item 3): body_NAME.csv gets a row a step with the
// body's state, run.json its last state; a run resumed from a checkpoint writes the same rows as one
// run straight.
#include "support.hpp"

#include <doctest/doctest.h>

#include <fstream>

using namespace cli_test;

namespace {

const std::string floating_scene = source + "/scenes/floating_box.json";
// scenes/floating_box.json with shallower water (fewer particles).
const std::vector<std::string> shallow = {"--set", "fluid[0].max=[0.8,0.125,0.1]", "--set",
                                          "boundaries.boxes[0].min=[0.32,0,0.2]", "--set", "boundaries.boxes[0].max=[0.48,0.12,0.32]"};

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("a floating box: body_box.csv a row a step, run.json its state, a resume the same rows") {
    const std::string straight = work_dir("floating_straight"), split = work_dir("floating_split");
    std::string log;
    REQUIRE(run(args({{"run", floating_scene}, shallow, {"--devices", "0", "--until", "0.006", "--every", "0.003", "--out", straight}}),
                log) == 0);
    INFO(log);
    const auto rows = read_csv_rows(straight + "/body_box.csv");
    const auto stats = read_csv_rows(straight + "/stats.csv");
    REQUIRE(rows.size() > 2);
    CHECK(rows.size() == stats.size());  // the header and a row a step, the start included
    CHECK(rows[0].size() == 20u);
    CHECK(rows[0][0] == "time");
    CHECK(rows[0][3] == "z");
    // Falling freely (the water is 0.1 m below it): z = z0 - g t^2 / 2, vz = -g t.
    const auto& last = rows.back();
    const double t = std::stod(last[0]), z0 = std::stod(rows[1][3]);
    CHECK(std::stod(last[3]) == doctest::Approx(z0 - 0.5 * 9.81 * t * t).epsilon(1e-6));
    CHECK(std::stod(last[10]) == doctest::Approx(-9.81 * t).epsilon(1e-6));
    const auto j = read_json(straight + "/run.json");
    REQUIRE(j.at("bodies").size() == 1);
    CHECK(j.at("bodies")[0].at("name") == "box");
    CHECK(j.at("bodies")[0].at("time").get<double>() == doctest::Approx(t));
    CHECK(j.at("bodies")[0].at("mass").get<double>() == doctest::Approx(500.0 * 0.17 * 0.13 * 0.13));

    REQUIRE(run(args({{"run", floating_scene}, shallow,
                      {"--devices", "0", "--until", "0.003", "--every", "0.003", "--out", split, "--checkpoint-every", "0.003"}}),
                log) == 0);
    REQUIRE(run({"resume", split, "--until", "0.006"}, log) == 0);
    CHECK(slurp(straight + "/body_box.csv") == slurp(split + "/body_box.csv"));
    CHECK(slurp(straight + "/stats.csv") == slurp(split + "/stats.csv"));
}
