// Inlets in time and across, and outlet zones, in scene files (docs/scenes.md, inlets and outlets):
// the feed at a speed from a CSV file makes its layers at the times and places the travelled
// distance gives (against the test's own integral of the file's rows), a profile makes each
// lattice column's layers by its factor, the keys round-trip through to_json, and hostile files
// and bad keys are errors naming the file, line and key.
#include "scene/open_boundaries.hpp"
#include "support.hpp"

#include <clsph/scene.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using scene_test::error_of;

namespace {

constexpr double kDp = 0.02;

// The channel of test_open_scene.cpp: the inlet's section y 0.02 .. 0.08 (4 points) by z 0.02 ..
// 0.06 (3 points), 4 layers; `inlet_extra` and `outlet` go into their objects.
std::string channel(const std::string& inlet_extra, const std::string& outlet = R"({"face": "x+"})",
                    const std::string& velocity = "[1, 0, 0]") {
    return R"({"physics": {"dp": 0.02}, "domain": {"min": [0, -0.06, -0.06], "max": [1, 0.16, 0.2]},
               "fluid": [{"min": [0.08, 0, 0], "max": [0.98, 0.1, 0.06]}],
               "boundaries": {"walls": [{"min": [0, 0, 0], "max": [0.98, 0.1, 0.2], "faces": ["y-", "y+", "z-"]}]},
               "inlets": [{"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": )" +
           velocity + inlet_extra + R"(}], "outlets": [)" + outlet + "]}";
}

// Rows of time, speed: linear between them, held beyond; the test's own integral of them.
struct Rows {
    std::vector<double> t, u;
    double speed(double x) const {
        if (x <= t.front()) return u.front();
        if (x >= t.back()) return u.back();
        std::size_t k = 0;
        while (t[k + 1] <= x) ++k;
        return u[k] + (u[k + 1] - u[k]) * (x - t[k]) / (t[k + 1] - t[k]);
    }
    double travelled(double x) const {  // Simpson's rule on each piece between rows (exact: the speed is linear there)
        std::vector<double> cuts{0.0};
        for (double r : t)
            if (r > 0 && r < x) cuts.push_back(r);
        cuts.push_back(x);
        double sum = 0;
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
            const double a = cuts[k], b = cuts[k + 1];
            sum += (b - a) / 6 * (speed(a) + 4 * speed(0.5 * (a + b)) + speed(b));
        }
        return sum;
    }
    std::string csv() const {
        std::ostringstream o;
        o.precision(17);
        o << "# time (s), speed (m/s)\ntime,speed\n";
        for (std::size_t k = 0; k < t.size(); ++k) o << t[k] << (k % 2 ? ", " : ",") << u[k] << (k % 3 ? "\r\n" : "\n");
        return o.str();
    }
};

Rows random_rows(std::mt19937_64& gen) {
    std::uniform_real_distribution<double> dt(0.005, 0.05), u(0.2, 1.5);
    Rows r;
    double t = -0.01;
    for (int k = 0; k < 12; ++k) {
        r.t.push_back(t);
        r.u.push_back(k == 3 ? 0.0 : u(gen));  // a row at rest too
        t += dt(gen);
    }
    return r;
}

// Writes the file beside a scene file and reads that scene (the CSV's path relative to it).
clsph::Scene scene_with_csv(const scene_test::TempDir& dir, const std::string& csv, const std::string& scene_text) {
    scene_test::write_text(dir.file("speed.csv"), csv);
    scene_test::write_text(dir.file("channel.json"), scene_text);
    return clsph::Scene::from_file(dir.file("channel.json"));
}

// Within 1e-9 m of a layer's threshold: the test's integral and the feed's may fall either side.
bool near_threshold(double x) { return std::abs(x / kDp - std::round(x / kDp)) < 1e-6; }

}  // namespace

TEST_SUITE("open_boundaries") {
TEST_CASE("a speed from a CSV file: each layer at the time X(t) reaches m dp, at upstream + X(t) - m dp") {
    std::mt19937_64 gen(scene_test::fresh_seed());
    scene_test::TempDir dir;
    const Rows rows = random_rows(gen);
    const clsph::Scene s = scene_with_csv(dir, rows.csv(), channel(R"(, "speed_csv": "speed.csv")"));
    REQUIRE(s.inlets[0].speed.time.size() == rows.t.size());
    clsph::scene::InletFeed feed(s, 500);
    CHECK(feed.due(0.0).size() == 48);  // the buffer: 4 layers of 12
    std::uniform_real_distribution<double> step(1e-4, 4e-3);
    std::uint32_t next = 548;
    std::int64_t layers = 0;  // the last layer made
    std::size_t calls = 0;
    for (double t = step(gen); t < rows.t.back() + 0.2; t += step(gen)) {
        const double x = rows.travelled(t);
        if (near_threshold(x)) continue;
        const clsph::Particles p = feed.due(t);
        const auto last = static_cast<std::int64_t>(std::floor(x / kDp));
        INFO("t = " << t << ", X = " << x);
        REQUIRE(p.size() == static_cast<std::size_t>(12 * (last - layers)));
        for (std::size_t i = 0; i < p.size(); ++i) {
            const std::int64_t m = layers + 1 + static_cast<std::int64_t>(i / 12);
            CHECK(p.id[i] == next++);
            CHECK(std::abs(p.position[i][0] - (x - static_cast<double>(m) * kDp)) <= 1e-12);
            CHECK(p.velocity[i][0] == static_cast<float>(rows.speed(t)));
        }
        layers = last;
        ++calls;
    }
    CHECK(layers >= 4);
    CHECK(calls > 50);
    // The buffer's step: exactly the travelled distance over dt.
    const clsph::scene::InletSpeed u(s.inlets[0]);
    for (int k = 0; k < 100; ++k) {
        const double t = step(gen) * 60, dt = step(gen);
        CHECK(std::abs(u.mean(t, dt) * dt - (rows.travelled(t + dt) - rows.travelled(t))) <= 1e-12);
        CHECK(std::abs(u.travelled(t) - rows.travelled(t)) <= 1e-12);
    }
}

TEST_CASE("a profile with a CSV speed: each lattice column makes floor(factor X(t) / dp) layers, ids by layer then column") {
    std::mt19937_64 gen(scene_test::fresh_seed());
    scene_test::TempDir dir;
    const Rows rows = random_rows(gen);
    // Factors along z: 0 at z = 0.02 (a column at rest), 1.5 at 0.06; linear between.
    const clsph::Scene s = scene_with_csv(dir, rows.csv(), channel(R"(, "speed_csv": "speed.csv",
        "profile": {"axis": "z", "points": [[0.02, 0], [0.06, 1.5]]})"));
    auto factor = [](double z) { return 1.5 * (z - 0.02) / 0.04; };
    clsph::scene::InletFeed feed(s, 0);
    CHECK(clsph::scene::inlet_streams(s) == 3);
    std::map<int, std::int64_t> made;  // per column (z index): particles after the buffer, over the 4 y points
    std::uint32_t last_id = 0;
    (void)feed.due(0.0);
    std::uniform_real_distribution<double> step(1e-4, 4e-3);
    const double end = rows.t.back() + 0.05;
    double last_t = 0.0;  // the feed has made the layers of X(last_t), not of X(end): up to 4 ms more
    for (double t = step(gen); t < end; t += step(gen)) {
        const clsph::Particles p = feed.due(t);
        last_t = t;
        std::int64_t m_prev = -1000;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const int col = static_cast<int>(std::lround(p.position[i][2] / kDp));
            const double xc = factor(col * kDp) * rows.travelled(t);
            // Its layer from its position; layers in order, each layer's particles in lattice order.
            const auto m = std::llround((xc - p.position[i][0]) / kDp);
            CHECK(std::abs(p.position[i][0] - (xc - static_cast<double>(m) * kDp)) <= 1e-9);
            CHECK(m >= m_prev);
            m_prev = m;
            CHECK(p.id[i] > last_id);
            last_id = p.id[i];
            CHECK(p.velocity[i][0] == static_cast<float>(rows.speed(t) * factor(col * kDp)));
            ++made[col];
        }
    }
    const double x = rows.travelled(last_t);
    for (int col = 1; col <= 3; ++col) {
        const double layers = std::floor(factor(col * kDp) * x / kDp);
        INFO("column z = " << col * kDp << ", X = " << x);
        if (!near_threshold(factor(col * kDp) * x)) CHECK(made[col] == static_cast<std::int64_t>(4 * layers));
    }
    CHECK(made[1] == 0);  // factor 0: never a new layer
    CHECK(made[3] > made[2]);
    // The memory plan is what fills the domain once whatever the speed: as without a profile.
    CHECK(clsph::scene::planned_with_inlets(s, 5000) == 5000 + 48 + 12 * 51);
    CHECK(feed.layers_per_second() == doctest::Approx(*std::max_element(rows.u.begin(), rows.u.end()) * 1.5 / kDp));
}

TEST_CASE("inlets in time and outlet zones: read, written back, and read again the same") {
    scene_test::TempDir dir;
    const std::string outlets = R"({"face": "x+"}, {"face": "x+", "min": [0.8, -0.06, -0.06], "max": [0.9, 0.16, 0.2], "pressure": 120},
        {"face": "z-", "min": [0.5, 0, 0], "max": [0.6, 0.1, 0.1], "level_csv": "level.csv"}, {"face": "x-", "min": [0.3, 0, 0], "max": [0.4, 0.1, 0.1], "level": 0.05})";
    scene_test::write_text(dir.file("level.csv"), "0, 0.06\n1, -0.02\n");
    const clsph::Scene s = scene_with_csv(dir, "0,0.1\n0.5,0.3\n",
                                          channel(R"(, "speed_csv": "speed.csv", "profile": {"axis": "y", "points": [[0, 1], [0.1, 0.5]]})", outlets));
    REQUIRE(s.outlets.size() == 4);
    CHECK(!s.outlets[0].zone);
    CHECK(s.outlets[1].zone);
    CHECK(*s.outlets[1].pressure == 120);
    CHECK(s.outlets[2].level_series.value == std::vector<double>{0.06, -0.02});
    CHECK(!s.outlets[2].upper);
    CHECK(*s.outlets[3].level == 0.05);
    CHECK(s.inlets[0].profile.axis == 1);
    CHECK(clsph::scene::has_outlet_zones(s));
    const std::string doc = s.to_json();
    CHECK(doc.find("speed_series") != std::string::npos);  // the file's rows: the resolved scene needs no file
    CHECK(doc.find("speed_csv") == std::string::npos);
    const clsph::Scene back = clsph::Scene::from_json_text(doc, "back.json");
    CHECK(back.to_json() == doc);
    CHECK(back.inlets[0].speed.value == std::vector<double>{0.1, 0.3});
    // A face-only outlet and a constant inlet write what they always did.
    const clsph::Scene plain = clsph::Scene::from_json_text(channel("", R"({"face": "x+"})", "[0.5, 0, 0]"), "c.json");
    const std::string d = plain.to_json();
    const auto a = d.find("\"outlets\""), b = d.find("\"run\"");
    REQUIRE(a < b);
    CHECK(d.substr(a, b - a).find("\"face\": \"x+\"") != std::string::npos);
    CHECK(d.substr(a, b - a).find("min") == std::string::npos);
    CHECK(d.find("speed") == std::string::npos);
    CHECK(d.find("profile") == std::string::npos);
    CHECK(!clsph::scene::has_outlet_zones(plain));
}

TEST_CASE("hostile speed and level files are errors naming the key, the file and the line") {
    scene_test::TempDir dir;
    auto err = [&](const std::string& csv) {
        return error_of([&] { (void)scene_with_csv(dir, csv, channel(R"(, "speed_csv": "speed.csv")")); });
    };
    auto has = [](const std::string& e, std::initializer_list<const char*> parts) {
        INFO(e);
        for (const char* p : parts) CHECK(e.find(p) != std::string::npos);
    };
    const char* key = "inlets[0].speed_csv";
    has(err("0,0.1\n0.5,-0.2\n"), {key, "speed.csv, line 2, column 2 (speed)", "must be >= 0"});
    has(err("0,0.1\n0.5,fast\n"), {key, "line 2, column 2 (speed)", "\"fast\" is not a number"});
    has(err("0,0.1\n0.5,nan\n"), {"line 2, column 2", "finite"});
    has(err("0,0.1\n0.5,1e300\n"), {"line 2", "beyond 1e9"});
    has(err("t,u\n0,0.1\n\n0,0.2\n"), {"line 4, column 1 (time)", "times must increase"});
    has(err("0,0.1\n"), {key, "at least 2"});
    has(err(""), {key, "has 0 rows"});
    has(err("0,0.1,3\n1,0.1,3\n"), {"line 1", "3 columns"});
    has(err("time,speed,extra\n0,1\n1,1\n"), {"line 1", "the header has 3 columns"});
    has(err("0,0.1\n1;0.2\n"), {"line 2", "1 columns"});
    has(err(std::string(5000, '7') + "\n"), {"line 1", "longer than"});
    has(err(std::string("0,0.1\n1,0.2\0\n", 13)), {"line 2", "\"0.2\\x00\" is not a number"});
    has(error_of([&] { (void)clsph::Scene::from_json_text(channel(R"(, "speed_csv": "/nonexistent/u.csv")"), "c.json"); }),
        {key, "/nonexistent/u.csv", "cannot open"});
    has(error_of([&] {
            scene_test::write_text(dir.file("level.csv"), "0, 0.06\n1, x\n");
            (void)scene_with_csv(dir, "0,1\n1,1\n",
                                 channel("", R"({"face": "x+", "min": [0.5, 0, 0], "max": [0.6, 0.1, 0.1], "level_csv": "level.csv"})"));
        }),
        {"outlets[0].level_csv", "level.csv, line 2, column 2 (level)"});
}

TEST_CASE("bad inlet and outlet keys are errors naming the key") {
    auto err = [](const std::string& inlet_extra, const std::string& outlet = R"({"face": "x+"})", const std::string& velocity = "[1, 0, 0]") {
        return error_of([&] { (void)clsph::Scene::from_json_text(channel(inlet_extra, outlet, velocity), "c.json"); });
    };
    auto has = [](const std::string& e, const std::string& what) {
        INFO(e);
        CHECK(e.find(what) != std::string::npos);
    };
    const std::string series = R"(, "speed_series": [[0, 0.2], [1, 0.4]])";
    has(err(series, R"({"face": "x+"})", "[0.5, 0, 0]"), "inlets[0].velocity: with a speed in time");
    has(err(R"(, "speed_series": [[0, 0.2], [1, -0.4]])"), "inlets[0].speed_series[1]: speed must be >= 0");
    has(err(R"(, "speed_series": [[0, 0.2], [0, 0.4]])"), "inlets[0].speed_series[1]: times must increase");
    has(err(R"(, "speed_series": [[0, 0.2]])"), "inlets[0].speed_series: a series needs at least 2 rows");
    has(err(R"(, "speed_series": [[0, 0.2, 3], [1, 1]])"), "inlets[0].speed_series[0]: expected 2 numbers");
    has(err(R"(, "speed_series": [[0, 0.2], [1, 1]], "speed_csv": "u.csv")"), "inlets[0].speed_series: give speed_csv or speed_series");
    has(err(R"(, "speed_csv": 3)"), "inlets[0].speed_csv");
    has(err(R"(, "speed_csv": "")"), "inlets[0].speed_csv: expected the path");
    has(err(R"(, "profile": {"axis": "x", "points": [[0, 1], [1, 1]]})"), "inlets[0].profile.axis: must lie across the flow");
    has(err(R"(, "profile": {"axis": "w", "points": [[0, 1], [1, 1]]})"), "inlets[0].profile.axis");
    has(err(R"(, "profile": {"points": [[0, 1], [1, 1]]})"), "inlets[0].profile.axis");
    has(err(R"(, "profile": {"axis": "z", "points": [[0, 1]]})"), "inlets[0].profile.points: expected at least 2");
    has(err(R"(, "profile": {"axis": "z", "points": [[0, 1], [0, 2]]})"), "inlets[0].profile.points[1]: the coordinates must increase");
    has(err(R"(, "profile": {"axis": "z", "points": [[0, 1], [1, -2]]})"), "inlets[0].profile.points[1]: the factor must be >= 0");
    has(err(R"(, "profile": {"axis": "z", "points": [[0, 1], [1, 2]], "shape": "parabolic"})"), "shape");
    const std::string box = R"("min": [0.5, 0, 0], "max": [0.6, 0.1, 0.1])";
    has(err("", R"({"face": "x+", "pressure": 10})"), "outlets[0].pressure: needs a zone");
    has(err("", R"({"face": "x+", "level": 0.1})"), "outlets[0].level: needs a zone");
    has(err("", R"({"face": "x+", "min": [0.5, 0, 0]})"), "outlets[0].max: missing required key");
    has(err("", R"({"face": "x+", )" + box + R"(, "pressure": 10, "level": 0.1})"), "outlets[0].level: give one of pressure, level");
    has(err("", R"({"face": "x+", )" + box + R"(, "pressure": -10})"), "outlets[0].pressure: must be a finite number >= 0");
    has(err("", R"({"face": "x+", )" + box + R"(, "level": "top"})"), "outlets[0].level");
    has(err("", R"({"face": "x+", "min": [0.5, 0, 0], "max": [0.505, 0.1, 0.1]})"), "outlets[0].max: the box must be at least dp");
    has(err("", R"({"face": "x+", "min": [0.5, 0, 0], "max": [1.5, 0.1, 0.1]})"), "outlets[0].max: the box must lie inside the domain");
    has(err("", R"({"face": "x+", )" + box + R"(, "level_series": [[0, 1], [-1, 1]]})"), "outlets[0].level_series[1]: times must increase");
    has(err("", R"({"face": "up", )" + box + "}"), "outlets[0].face");
    has(err("", R"({)" + box + "}"), "outlets[0].face");
    has(err("", R"({"face": "x+", )" + box + R"(, "height": 1})"), "height");
}
}
