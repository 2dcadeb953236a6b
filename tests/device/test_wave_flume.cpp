// The wave maker in water (issue 32 item 2; scenes/wave_flume.json at CI's size): a piston flume
// 0.1 m deep at d / dp = 7, a thin periodic slice, waves of period 0.72 s (kd = 1.0) ramped over half
// a period; the first waves' height at a gauge 0.3 m (half a wavelength) from the paddle, crest to trough per period
// after the ramp and before anything reflected from the far wall can return, against Biesel's
// prediction (the wave maker was asked for it), within 20 %.
#include "clsph/simulation.hpp"
#include "scene/wave_maker.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace clsph;

namespace {

constexpr double kDepth = 0.1, kHeight = 0.02, kPeriod = 0.72, kDp = 0.1 / 7, kLength = 0.75, kGauge = 0.3;
constexpr int kSlice = 12;  // lattice lines across the periodic y

// `maker`: the wave_maker's type and its own keys.
std::string flume(const std::string& maker) {
    const std::string d = std::to_string(kDepth), dp = std::to_string(kDp), len = std::to_string(kLength);
    const std::string width = std::to_string(kSlice * kDp), wall_y = std::to_string(kSlice * kDp - 0.5 * kDp);
    return R"({
  "name": "short flume",
  "physics": {"dp": )" + dp + R"(, "hdp": 2.0, "coefsound": 8, "alpha": 0.02, "cfl": 0.2},
  "domain": {"min": [-0.1, 0, -0.05], "max": [)" + std::to_string(kLength + 0.05) + R"(, )" + width + R"(, 0.3],
             "periodic": [false, true, false], "split_axis": "x"},
  "fluid": [{"min": [)" + std::to_string(3 * kDp) + R"(, 0, 0], "max": [)" + len + R"(, )" + wall_y + R"(, )" + d + R"(]}],
  "boundaries": {
    "walls": [{"min": [-0.08, 0, 0], "max": [)" + len + R"(, )" + wall_y + R"(, 0.25], "faces": ["x+", "z-"], "layers": 3}],
    "boxes": [{"min": [0, 0, )" + dp + R"(], "max": [)" + std::to_string(2 * kDp) + R"(, )" + wall_y + R"(, 0.2], "layers": 0,
               "motion": {"wave_maker": {)" + maker + R"(, "height": )" + std::to_string(kHeight) + R"(, "period": )" +
           std::to_string(kPeriod) + R"(, "depth": )" + d + R"(, "ramp": 0.36}}}]
  },
  "probes": [{"name": "gauge", "kind": "height", "point": [)" + std::to_string(kGauge) + R"(, 0.05]}],
  "run": {"end_time": 1.55, "probe_every": 1}
})";
}

// The mean crest-to-trough height over whole periods of the gauge's signal in [from, to).
double wave_height(const std::vector<std::pair<double, double>>& signal, double from, double to) {
    double sum = 0;
    int n = 0;
    for (double t0 = from; t0 + kPeriod <= to + 1e-9; t0 += kPeriod) {
        double hi = -1e9, lo = 1e9;
        for (const auto& [t, h] : signal)
            if (t >= t0 && t < t0 + kPeriod && std::isfinite(h)) hi = std::max(hi, h), lo = std::min(lo, h);
        MESSAGE("period from " << t0 << " s: crest " << hi << " m, trough " << lo << " m, height " << hi - lo << " m");
        sum += hi - lo;
        ++n;
    }
    return sum / n;
}

// Runs the flume on the first device; returns the measured height and the one asked for.
double measured_height(const Scene& scene) {
    auto* dev = test::devices().front();
    MESSAGE("device " << dev->label());
    Options o;
    o.devices = std::to_string(dev->info().index);
    Simulation sim(scene, o);
    std::vector<std::pair<double, double>> signal;
    int steps = 0;
    while (sim.time() < scene.run.end_time) {
        sim.step();
        if (++steps % 4 == 0) signal.emplace_back(sim.time(), sim.sample_probes().at(0).value);
    }
    // The wave front (group speed) passes the gauge after the ramp; what the far wall reflects
    // comes back after (2 L - x) / c_g.
    const auto& w = *scene.solids[0].motion.wave_maker;
    const double kd = w.k * w.depth, c = w.wavelength / w.period, cg = 0.5 * c * (1 + 2 * kd / std::sinh(2 * kd));
    const double from = w.ramp + kGauge / cg, back = (2 * kLength - kGauge) / cg;
    MESSAGE(steps << " steps; kd " << kd << ", wavelength " << w.wavelength << " m, stroke " << w.stroke << " m; measured from "
                  << from << " s, reflections back at " << back << " s");
    REQUIRE(back > scene.run.end_time);
    return wave_height(signal, from, scene.run.end_time);
}

}  // namespace

TEST_SUITE("wave_flume") {
TEST_CASE("a piston's first waves in a short flume: their height within 20 % of Biesel's prediction") {
    const Scene s = Scene::from_json_text(flume(R"("type": "piston")"), "short_flume.json");
    const double h = measured_height(s);
    MESSAGE("piston: wave height " << h << " m, asked for " << kHeight << " m (" << 100 * (h / kHeight - 1) << " %)");
    CHECK(std::abs(h / kHeight - 1) < 0.2);
}

TEST_CASE("a flap's first waves in the same flume: their height within 20 % of its transfer function's prediction") {
    // Hinged at the bed under the paddle's middle.
    const std::string hinge = R"("type": "flap", "hinge": [)" + std::to_string(kDp) + R"(, 0, 0])";
    const Scene s = Scene::from_json_text(flume(hinge), "short_flume.json");
    const double h = measured_height(s);
    MESSAGE("flap: wave height " << h << " m, asked for " << kHeight << " m (" << 100 * (h / kHeight - 1) << " %)");
    CHECK(std::abs(h / kHeight - 1) < 0.2);
}
}
