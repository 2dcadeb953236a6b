// Motions from elsewhere (issue 32 items 1 and 2): a CSV file of rows turned into intervals, and
// wave makers from first-order wave-maker theory. The dispersion solver and Biesel's transfer
// functions against values computed here independently (bisection, the textbook forms, numerical
// quadrature of the transfer integral, deep and shallow-water limits); the CSV motion's poses
// against the rows' own formula; bad files and bad wave makers as errors naming file, line, key.
#include "support.hpp"

#include "scene/motion.hpp"
#include "scene/wave_maker.hpp"

#include <clsph/scene.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>
#include <string>

using scene_test::error_of;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string scene_with(const std::string& motion) {
    return R"({
  "physics": {"dp": 0.02},
  "domain": {"min": [-0.1, -0.1, -0.1], "max": [2.1, 0.5, 1.1]},
  "fluid": [{"min": [0.1, 0, 0], "max": [2, 0.4, 0.4]}],
  "boundaries": {
    "walls": [{"min": [0, 0, 0], "max": [2, 0.4, 1]}],
    "boxes": [{"min": [0.02, 0, 0], "max": [0.06, 0.4, 0.6], "motion": )" +
           motion + R"(}]
  },
  "run": {"end_time": 3}
})";
}

// kd of x tanh x = y by bisection.
double kd_bisect(double period, double depth, double g) {
    const double w = 2 * kPi / period, y = w * w * depth / g;
    double lo = 0, hi = std::max(1.0, 2 * y + 2 * std::sqrt(y));
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (mid * std::tanh(mid) < y ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// H/S = 4 sinh x / (sinh 2x + 2x) * k Int_0^d f cosh(k s) ds with d = 1, k = x, f the flap's
// displacement profile (0 below the hinge at lambda, linear to 1 at the surface), by Simpson.
double flap_by_quadrature(double x, double lambda) {
    const int n = 200000;
    const double h = 1.0 / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        const double s = i * h, f = s > lambda ? (s - lambda) / (1 - lambda) : 0.0;
        sum += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * f * std::cosh(x * s);
    }
    return 4 * std::sinh(x) / (std::sinh(2 * x) + 2 * x) * x * sum * h / 3;
}

using Mat = std::array<double, 9>;
Mat mul(const Mat& a, const Mat& b) {
    Mat c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
    return c;
}
// Rz(c) Ry(b) Rx(a), degrees.
Mat euler_deg(double a, double b, double c) {
    a *= kPi / 180, b *= kPi / 180, c *= kPi / 180;
    const Mat rx{1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a)};
    const Mat ry{std::cos(b), 0, std::sin(b), 0, 1, 0, -std::sin(b), 0, std::cos(b)};
    const Mat rz{std::cos(c), -std::sin(c), 0, std::sin(c), std::cos(c), 0, 0, 0, 1};
    return mul(rz, mul(ry, rx));
}

}  // namespace

TEST_CASE("the dispersion relation: Newton's kd solves w^2 = g k tanh(kd), with the deep and shallow-water limits") {
    std::random_device rd;
    const auto seed = rd();
    MESSAGE("seed " << seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> lg(-2.0, 2.0);
    for (int i = 0; i < 200; ++i) {
        const double T = std::pow(10.0, 0.5 * lg(rng)), d = std::pow(10.0, lg(rng)), g = 9.81;
        const double kd = clsph::scene::wave_number_depth(T, d, g), want = kd_bisect(T, d, g);
        CHECK(std::abs(kd - want) <= 1e-12 * want);
    }
    const double w = 2 * kPi / 1.0;
    CHECK(std::abs(clsph::scene::wave_number_depth(1.0, 100.0, 9.81) - w * w * 100.0 / 9.81) < 1e-10);  // deep: k = w^2 / g
    const double shallow = clsph::scene::wave_number_depth(100.0, 0.1, 9.81), c = std::sqrt(9.81 * 0.1);
    CHECK(std::abs(shallow - 2 * kPi / 100.0 / c * 0.1) < 1e-4 * shallow);  // shallow: k = w / sqrt(g d)
}

TEST_CASE("Biesel's transfer functions: the textbook forms, the transfer integral, and their limits") {
    for (double x = 0.05; x < 6; x *= 1.3) {
        const double piston = 2 * (std::cosh(2 * x) - 1) / (std::sinh(2 * x) + 2 * x);
        CHECK(std::abs(clsph::scene::piston_height_ratio(x) - piston) < 1e-12 * piston);
        const double flap = 4 * std::sinh(x) / (std::sinh(2 * x) + 2 * x) * (x * std::sinh(x) - std::cosh(x) + 1) / x;
        CHECK(std::abs(clsph::scene::flap_height_ratio(x, 0.0) - flap) < 1e-10 * flap);
        for (double lambda : {0.0, 0.25, 0.6}) {
            const double q = flap_by_quadrature(x, lambda);
            CHECK(std::abs(clsph::scene::flap_height_ratio(x, lambda) - q) < 1e-7 * q);
        }
    }
    CHECK(std::abs(clsph::scene::piston_height_ratio(30.0) - 2.0) < 1e-12);  // deep water
    CHECK(std::abs(clsph::scene::flap_height_ratio(30.0, 0.0) - 2.0 * (1 - 1 / 30.0)) < 1e-12);
    CHECK(std::abs(clsph::scene::piston_height_ratio(1e-3) - 1e-3) < 1e-8);  // shallow: H/S = kd
    CHECK(std::abs(clsph::scene::flap_height_ratio(1e-3, 0.0) - 0.5e-3) < 1e-8);  // and kd / 2
    CHECK(clsph::scene::piston_height_ratio(800.0) == doctest::Approx(2.0));  // no overflow
    CHECK(clsph::scene::flap_height_ratio(800.0, 0.3) == doctest::Approx(2.0).epsilon(1e-2));
}

TEST_CASE("a wave maker's stroke, wavelength and segment; read, written back and read again the same") {
    const double H = 0.04, T = 1.4, d = 0.4, g = 9.81;
    const clsph::Scene s = clsph::Scene::from_json_text(
        scene_with(R"({"wave_maker": {"type": "piston", "height": 0.04, "period": 1.4, "depth": 0.4, "ramp": 1.5}})"), "flume.json");
    const auto& m = s.solids[0].motion;
    REQUIRE(m.wave_maker);
    REQUIRE(m.segments.size() == 1);
    const double kd = kd_bisect(T, d, g);
    const double ratio = 2 * (std::cosh(2 * kd) - 1) / (std::sinh(2 * kd) + 2 * kd);
    MESSAGE("piston: kd " << kd << ", L " << 2 * kPi * d / kd << " m, stroke " << H / ratio << " m");
    CHECK(m.wave_maker->k == doctest::Approx(kd / d).epsilon(1e-12));
    CHECK(m.wave_maker->wavelength == doctest::Approx(2 * kPi * d / kd).epsilon(1e-12));
    CHECK(m.wave_maker->stroke == doctest::Approx(H / ratio).epsilon(1e-12));
    const auto& seg = m.segments[0];
    CHECK(seg.type == clsph::MotionSegment::Type::ramped_sine);
    CHECK(seg.amplitude[0] == doctest::Approx(0.5 * H / ratio).epsilon(1e-12));
    CHECK(seg.amplitude[1] == 0);
    CHECK(seg.end == 3.0);  // the run's end
    CHECK(seg.ramp == 1.5);
    // The displacement ramps up from rest: zero, then growing, the full amplitude after the ramp.
    const clsph::Vec3 x0{0.04, 0.2, 0.2};
    auto at = [&](double t) { return clsph::scene::motion_pose(m, t).apply(x0)[0] - x0[0]; };
    CHECK(at(0) == 0);
    CHECK(at(1.4 + 0.35) == doctest::Approx(0.5 * H / ratio).epsilon(1e-9));  // a crest after the ramp: w t = pi / 2 + 2 pi
    const double v = clsph::scene::motion_velocity(m, 0.7, x0)[0], fd = (at(0.7 + 1e-6) - at(0.7 - 1e-6)) / 2e-6;
    CHECK(std::abs(v - fd) < 1e-6);
    // Read back from the resolved scene: the same segment, bit for bit.
    const clsph::Scene again = clsph::Scene::from_json_text(s.to_json(), "again.json");
    const auto& seg2 = again.solids[0].motion.segments.at(0);
    CHECK(std::memcmp(&seg2.amplitude, &seg.amplitude, sizeof seg.amplitude) == 0);
    CHECK(again.to_json() == s.to_json());

    const clsph::Scene f = clsph::Scene::from_json_text(
        scene_with(R"({"wave_maker": {"type": "flap", "height": 0.04, "period": 1.4, "depth": 0.4, "hinge": [0.04, 0, 0.1], "hinge_height": 0.1}})"),
        "flume.json");
    const auto& fs = f.solids[0].motion.segments.at(0);
    const double lambda = 0.25, fr = flap_by_quadrature(kd, lambda);
    CHECK(fs.type == clsph::MotionSegment::Type::ramped_sine_rotation);
    CHECK(f.solids[0].motion.wave_maker->stroke == doctest::Approx(H / fr).epsilon(1e-6));
    CHECK(fs.angle == doctest::Approx(std::atan(0.5 * H / fr / 0.3)).epsilon(1e-6));
    CHECK(fs.axis[1] == doctest::Approx(1.0));  // up x direction: the top moves along +x first
    CHECK(fs.ramp == doctest::Approx(2.8));     // two periods by default
    CHECK(clsph::scene::motion_velocity(f.solids[0].motion, 0.3, {0.04, 0.2, 0.5})[0] > 0);
    CHECK(clsph::Scene::from_json_text(f.to_json(), "again.json").to_json() == f.to_json());
}

TEST_CASE("bad wave makers are errors naming the key and the value") {
    auto err = [](const std::string& w) { return error_of([&] { (void)clsph::Scene::from_json_text(scene_with(R"({"wave_maker": )" + w + "}"), "flume.json"); }); };
    const std::string at = "boundaries.boxes[0].motion.wave_maker";
    std::string e = err(R"({"type": "piston", "height": 0.04, "period": 1.4, "depth": 0})");
    CHECK(e.find("flume.json") != std::string::npos);
    CHECK(e.find(at + ".depth") != std::string::npos);
    e = err(R"({"type": "piston", "height": 0.3, "period": 1.0, "depth": 0.5})");
    CHECK(e.find(at + ".height") != std::string::npos);
    CHECK(e.find("breaking limit") != std::string::npos);
    e = err(R"({"type": "piston", "height": -0.1, "period": 1.0, "depth": 0.5})");
    CHECK(e.find(at + ".height") != std::string::npos);
    e = err(R"({"type": "flap", "height": 0.04, "period": 1.4, "depth": 0.4, "hinge": [0, 0, 0], "hinge_height": 0.4})");
    CHECK(e.find(at + ".hinge_height") != std::string::npos);
    e = err(R"({"type": "flap", "height": 0.04, "period": 1.4, "depth": 0.4})");
    CHECK(e.find(at + ".hinge") != std::string::npos);
    e = err(R"({"type": "piston", "height": 0.04, "period": 1.4, "depth": 0.4, "hinge": [0, 0, 0]})");
    CHECK(e.find(at + ".hinge") != std::string::npos);
    e = err(R"({"type": "piston", "height": 0.04, "period": 1.4, "depth": 0.4, "direction": [1, 0, 1]})");
    CHECK(e.find(at + ".direction") != std::string::npos);
    e = err(R"({"type": "piston", "height": 0.04, "period": 1.4, "depth": 0.4, "stroke": 1})");
    CHECK(e.find(at + ".stroke") != std::string::npos);
    e = err(R"({"type": "paddle", "height": 0.04, "period": 1.4, "depth": 0.4})");
    CHECK(e.find(at + ".type") != std::string::npos);
    e = err(R"({"type": "piston", "height": 0.04, "period": 1.4, "depth": 0.4, "ramp": -1})");
    CHECK(e.find(at + ".ramp") != std::string::npos);
}

TEST_CASE("a motion from a CSV file: at each row the solid is where the row says, interpolated between, velocity the interpolation's") {
    std::random_device rd;
    const auto seed = rd();
    MESSAGE("seed " << seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    scene_test::TempDir dir;
    const int rows = 60;
    std::vector<std::array<double, 7>> r(rows);
    std::ostringstream csv;
    csv.precision(17);
    csv << "# a random motion\ntime,x,y,z,rx,ry,rz\n";
    double t = 0.1 + 0.05 * (u(rng) + 1);
    for (int k = 0; k < rows; ++k) {
        const auto prev = k ? r[k - 1] : std::array<double, 7>{0, 1, 2, 3, 10, -5, 20};
        r[k] = {t, prev[1] + 0.01 * u(rng), prev[2] + 0.01 * u(rng), prev[3] + 0.01 * u(rng), prev[4] + 20 * u(rng),
                prev[5] + 20 * u(rng), prev[6] + 20 * u(rng)};
        csv << r[k][0] << ", " << r[k][1] << "," << r[k][2] << "," << r[k][3] << "," << r[k][4] << "," << r[k][5] << "," << r[k][6] << "\n";
        t += 0.001 + 0.02 * (u(rng) + 1);
    }
    scene_test::write_text(dir.file("motion.csv"), csv.str());
    const clsph::Scene s = clsph::Scene::from_json_text(
        scene_with(R"({"segments": [{"type": "csv", "file": ")" + dir.file("motion.csv") + R"(", "center": [0.04, 0.2, 0.3]}]})"), "flume.json");
    const auto& m = s.solids[0].motion;
    REQUIRE(m.segments.size() == rows - 1u);
    const clsph::Vec3 c{0.04, 0.2, 0.3}, x0{0.05, 0.1, 0.5};
    const Mat e0 = euler_deg(r[0][4], r[0][5], r[0][6]);
    const Mat e0t{e0[0], e0[3], e0[6], e0[1], e0[4], e0[7], e0[2], e0[5], e0[8]};
    double worst = 0;
    for (int k = 0; k < rows; ++k) {
        const Mat q = mul(euler_deg(r[k][4], r[k][5], r[k][6]), e0t);
        const clsph::Vec3 got = clsph::scene::motion_pose(m, r[k][0]).apply(x0);
        for (int a = 0; a < 3; ++a) {
            double want = c[a] + r[k][1 + a] - r[0][1 + a];
            for (int b = 0; b < 3; ++b) want += q[3 * a + b] * (x0[b] - c[b]);
            worst = std::max(worst, std::abs(got[a] - want));
        }
    }
    MESSAGE("worst position at the rows " << worst << " m");
    CHECK(worst < 1e-12);
    // Between rows: velocity against the pose's central difference; before and after: at rest.
    double worst_v = 0;
    for (int k = 0; k + 1 < rows; ++k) {
        const double tm = 0.5 * (r[k][0] + r[k + 1][0]), h = 1e-7;
        const auto v = clsph::scene::motion_velocity(m, tm, x0);
        const auto a = clsph::scene::motion_pose(m, tm + h).apply(x0), b = clsph::scene::motion_pose(m, tm - h).apply(x0);
        for (int i = 0; i < 3; ++i) worst_v = std::max(worst_v, std::abs(v[i] - (a[i] - b[i]) / (2 * h)) / (1 + std::abs(v[i])));
    }
    CHECK(worst_v < 1e-5);
    CHECK(clsph::scene::motion_velocity(m, r[0][0] - 0.01, x0) == clsph::Vec3{0, 0, 0});
    CHECK(clsph::scene::motion_velocity(m, r[rows - 1][0] + 0.01, x0) == clsph::Vec3{0, 0, 0});
    // One angle changing: the angle is interpolated linearly between rows.
    scene_test::write_text(dir.file("flap.csv"), "0,0,0,0,0,0,0\n1,0.1,0,0,0,30,0\n");
    const clsph::Scene f = clsph::Scene::from_json_text(
        scene_with(R"({"segments": [{"type": "csv", "file": ")" + dir.file("flap.csv") + R"(", "center": [0, 0, 0]}]})"), "flume.json");
    const clsph::Vec3 p = clsph::scene::motion_pose(f.solids[0].motion, 0.25).apply({0, 0, 1});
    CHECK(p[0] == doctest::Approx(0.025 + std::sin(7.5 * kPi / 180)).epsilon(1e-12));
    CHECK(p[2] == doctest::Approx(std::cos(7.5 * kPi / 180)).epsilon(1e-12));
    // Positions only: no center; written back and read again the same (as its intervals).
    scene_test::write_text(dir.file("piston.csv"), "0, 0, 0, 0\n0.5, 0.01, 0, 0\n1.0, -0.01, 0, 0.002\n");
    const clsph::Scene pc = clsph::Scene::from_json_text(
        scene_with(R"({"segments": [{"type": "csv", "file": ")" + dir.file("piston.csv") + R"("}]})"), "flume.json");
    CHECK(clsph::scene::motion_velocity(pc.solids[0].motion, 0.7, x0)[0] == doctest::Approx(-0.04));
    CHECK(clsph::Scene::from_json_text(pc.to_json(), "again.json").to_json() == pc.to_json());
}

TEST_CASE("bad motion files are errors naming the file, line and column") {
    scene_test::TempDir dir;
    auto err = [&](const std::string& text, const std::string& extra = "") {
        scene_test::write_text(dir.file("m.csv"), text);
        return error_of([&] {
            (void)clsph::Scene::from_json_text(
                scene_with(R"({"segments": [{"type": "csv", "file": ")" + dir.file("m.csv") + "\"" + extra + "}]}"), "flume.json");
        });
    };
    const std::string at = "boundaries.boxes[0].motion.segments[0].file";
    std::string e = err("0,0,0,0\n0.1,0,abc,0\n");
    CHECK(e.find("flume.json") != std::string::npos);
    CHECK(e.find(at) != std::string::npos);
    CHECK(e.find("m.csv, line 2, column 3 (y)") != std::string::npos);
    CHECK(e.find("\"abc\" is not a number") != std::string::npos);
    e = err("0,0,0,0\n0.1,0,0,nan\n");
    CHECK(e.find("line 2, column 4 (z)") != std::string::npos);
    CHECK(e.find("finite") != std::string::npos);
    e = err("0,0,0,0\n0.1,0,0,inf\n");
    CHECK(e.find("line 2, column 4 (z)") != std::string::npos);
    e = err("t,x,y,z\n0,0,0,0\n\n0.2,0,0,0\n0.2,0,0,0\n");
    CHECK(e.find("line 5, column 1 (time)") != std::string::npos);
    CHECK(e.find("times must increase") != std::string::npos);
    e = err("t,x,y,z\n0,0,0,0\n");
    CHECK(e.find("at least 2") != std::string::npos);
    e = err("0,0,0,0\n0.1,0,0\n");
    CHECK(e.find("line 2") != std::string::npos);
    CHECK(e.find("columns") != std::string::npos);
    e = err("0,0,0,0,0,0,0\n0.1,0,0,0,0,0,5\n");
    CHECK(e.find("motion.segments[0].center") != std::string::npos);
    e = err("0,0,0,0\n1,0,0,0\n", R"(, "center": [0, 0, 0])");
    CHECK(e.find("motion.segments[0].center") != std::string::npos);
    e = error_of([&] {
        (void)clsph::Scene::from_json_text(scene_with(R"({"segments": [{"type": "csv", "file": "/nonexistent/m.csv"}]})"), "flume.json");
    });
    CHECK(e.find("/nonexistent/m.csv") != std::string::npos);
    CHECK(e.find("cannot open") != std::string::npos);
    e = err(std::string(5000, '1') + "\n");
    CHECK(e.find("longer than") != std::string::npos);
}
