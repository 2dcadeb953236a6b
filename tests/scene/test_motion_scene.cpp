// Prescribed motion in scene files (issue 32): every segment type read and written back, the
// closed form's poses, and the errors of bad motions naming the file and the key.
#include "support.hpp"

#include "scene/motion.hpp"

#include <clsph/scene.hpp>

#include <cmath>
#include <string>

using scene_test::error_of;

namespace {

// A tank whose box moves by `motion` (a JSON value).
std::string scene_with(const std::string& motion, const std::string& method = "dbc") {
    return R"({
  "physics": {"dp": 0.02},
  "domain": {"min": [-0.1, -0.1, -0.1], "max": [1.1, 0.5, 1.1]},
  "fluid": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.3]}],
  "boundaries": {
    "walls": [{"min": [0, 0, 0], "max": [1, 0.4, 1]}],
    "boxes": [{"min": [0.6, 0, 0], "max": [0.7, 0.4, 0.1], "motion": )" +
           motion + R"(}],
    "method": ")" + method + R"("
  }
})";
}

const char* all_types = R"({"segments": [
  {"type": "linear", "start": 0, "end": 0.1, "velocity": [0.5, 0, 0]},
  {"type": "sine", "start": 0.1, "end": 0.3, "amplitude": [0.02, 0, 0.01], "period": 0.2, "phase": 0.5},
  {"type": "sine_rotation", "start": 0.3, "end": 0.5, "axis_point": [0.65, 0.2, 0], "axis": [0, 2, 0], "angle": 0.1, "period": 0.4},
  {"type": "rotation", "start": 0.6, "end": 0.7, "axis_point": [0.65, 0.2, 0.05], "axis": [0, 0, 1], "angular_velocity": 1.5}
]})";

}  // namespace

TEST_CASE("a solid's motion: every segment type read, written back and read again the same") {
    const clsph::Scene s = clsph::Scene::from_json_text(scene_with(all_types), "tank.json");
    REQUIRE(s.solids.size() == 1);
    const auto& seg = s.solids[0].motion.segments;
    REQUIRE(seg.size() == 4);
    using Type = clsph::MotionSegment::Type;
    CHECK(seg[0].type == Type::linear);
    CHECK(seg[0].velocity == clsph::Vec3{0.5, 0, 0});
    CHECK(seg[1].type == Type::sine);
    CHECK(seg[1].amplitude == clsph::Vec3{0.02, 0, 0.01});
    CHECK(seg[1].period == 0.2);
    CHECK(seg[1].phase == 0.5);
    CHECK(seg[2].type == Type::sine_rotation);
    CHECK(seg[2].axis == clsph::Vec3{0, 2, 0});
    CHECK(seg[2].angle == 0.1);
    CHECK(seg[2].phase == 0.0);
    CHECK(seg[3].type == Type::rotation);
    CHECK(seg[3].angular_velocity == 1.5);
    CHECK(s.has_motion());
    const clsph::Scene back = clsph::Scene::from_json_text(s.to_json(), "back.json");
    CHECK(back.to_json() == s.to_json());
    REQUIRE(back.solids[0].motion.segments.size() == 4);
    CHECK(back.solids[0].motion.segments[2].axis_point == clsph::Vec3{0.65, 0.2, 0});
    // Without a motion nothing is written: resolved scenes of still solids are as before.
    const clsph::Scene still = clsph::Scene::from_json_text(scene_with("null"), "still.json");
    CHECK(!still.has_motion());
    CHECK(still.to_json().find("motion") == std::string::npos);
}

TEST_CASE("a motion's closed form: rests before, between and after its segments") {
    const clsph::Scene s = clsph::Scene::from_json_text(scene_with(all_types), "tank.json");
    const auto& m = s.solids[0].motion;
    const clsph::Vec3 x0{0.6, 0.1, 0.04};
    auto at = [&](double t) { return clsph::scene::motion_pose(m, t).apply(x0); };
    CHECK(at(-1.0) == x0);
    CHECK(at(0.05)[0] == doctest::Approx(0.6 + 0.025));
    // The sine starts where the linear segment left the box (continuous), and so on.
    CHECK(at(0.1)[0] == doctest::Approx(0.65));
    const double w = 2 * M_PI / 0.2;
    CHECK(at(0.15)[0] == doctest::Approx(0.65 + 0.02 * (std::sin(w * 0.05 + 0.5) - std::sin(0.5))));
    // Between 0.5 and 0.6 and after 0.7 the solid rests.
    CHECK(at(0.55) == at(0.5));
    CHECK(at(2.0) == at(0.7));
    const auto v = clsph::scene::motion_velocity(m, 0.55, x0);
    CHECK(v == clsph::Vec3{0, 0, 0});
    CHECK(clsph::scene::motion_velocity(m, 0.05, x0) == clsph::Vec3{0.5, 0, 0});
    // The rotation: a point on the axis stays; one off it keeps its distance.
    const clsph::Vec3 on_axis{0.65, 0.2, 0.05};
    const auto p = clsph::scene::motion_pose(m, 0.65);
    const auto q0 = clsph::scene::motion_pose(m, 0.6);
    const auto a = p.apply(x0), b = q0.apply(x0);
    const double ra = std::hypot(a[0] - on_axis[0], a[1] - on_axis[1]), rb = std::hypot(b[0] - on_axis[0], b[1] - on_axis[1]);
    CHECK(ra == doctest::Approx(rb));
    CHECK(a[2] == doctest::Approx(b[2]));
}

TEST_CASE("bad motions are errors naming the file and the key") {
    auto err = [](const std::string& motion, const std::string& method = "dbc") {
        return error_of([&] { (void)clsph::Scene::from_json_text(scene_with(motion, method), "tank.json"); });
    };
    const std::string at = "boundaries.boxes[0].motion.segments[";
    std::string e = err(R"({"segments": [{"type": "linear", "start": 0.2, "end": 0.1, "velocity": [1, 0, 0]}]})");
    CHECK(e.find("tank.json") != std::string::npos);
    CHECK(e.find(at + "0].end") != std::string::npos);
    e = err(R"({"segments": [{"type": "linear", "start": 0, "end": 0.2, "velocity": [1, 0, 0]},
                             {"type": "linear", "start": 0.1, "end": 0.3, "velocity": [1, 0, 0]}]})");
    CHECK(e.find(at + "1].start") != std::string::npos);
    CHECK(e.find("overlaps") != std::string::npos);
    e = err(R"({"segments": [{"type": "sine_rotation", "start": 0, "end": 1, "axis_point": [0, 0, 0], "axis": [0, 0, 0], "angle": 0.1, "period": 1}]})");
    CHECK(e.find(at + "0].axis") != std::string::npos);
    e = err(R"({"segments": [{"type": "sine", "start": 0, "end": 1, "amplitude": [0.1, 0, 0], "period": 0}]})");
    CHECK(e.find(at + "0].period") != std::string::npos);
    e = err(R"({"segments": [{"type": "sine", "start": 0, "end": 1, "amplitude": [0.1, 0, 0], "period": -1}]})");
    CHECK(e.find(at + "0].period") != std::string::npos);
    e = err(R"({"segments": [{"type": "linear", "start": 0, "end": 1, "velocity": [1, 0, 0], "period": 1}]})");
    CHECK(e.find(at + "0].period") != std::string::npos);
    CHECK(e.find("not a key of a \"linear\" segment") != std::string::npos);
    e = err(R"({"segments": [{"type": "wobble", "start": 0, "end": 1}]})");
    CHECK(e.find(at + "0].type") != std::string::npos);
    e = err(R"({"segments": [{"type": "linear", "start": 0, "end": 1}]})");
    CHECK(e.find(at + "0].velocity") != std::string::npos);
    e = err(R"({"segments": [{"type": "linear", "start": 0, "end": 1, "velocity": [1, "a", 0]}]})");
    CHECK(e.find(at + "0].velocity") != std::string::npos);
    // mDBC moves the ghost nodes with the solid: a moving solid is fine there.
    CHECK(clsph::Scene::from_json_text(scene_with(R"({"segments": [{"type": "linear", "start": 0, "end": 1, "velocity": [1, 0, 0]}]})", "mdbc"),
                                       "tank.json")
              .has_motion());
    // Scenes built in C++ are checked alike.
    clsph::Scene s = clsph::Scene::from_json_text(scene_with("null"), "tank.json");
    clsph::MotionSegment bad;
    bad.type = clsph::MotionSegment::Type::linear;
    bad.start = 0;
    bad.end = std::nan("");
    s.solids[0].motion.segments.push_back(bad);
    e = error_of([&] { s.validate(); });
    CHECK(e.find(at + "0].end") != std::string::npos);
}
