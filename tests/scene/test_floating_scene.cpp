// Floating bodies in scene files (issue 32 item 3): the floating object read and written back, the
// mass, centre and inertia computed from the particles, and the errors of bad ones naming the file
// and the key.
#include "support.hpp"

#include "scene/floating.hpp"

#include <clsph/scene.hpp>

#include <cmath>
#include <string>

using scene_test::error_of;

namespace {

// A tank with water and a filled box at [0.5, 0.7] x [0.1, 0.3] x [0.2, 0.3] with `floating`, and
// `extra` keys of the box.
std::string scene_with(const std::string& floating, const std::string& extra = "", const std::string& method = "dbc",
                       int layers = 0) {
    return R"({
  "physics": {"dp": 0.05},
  "domain": {"min": [-0.2, -0.2, -0.2], "max": [1.2, 0.6, 1.2]},
  "fluid": [{"min": [0, 0, 0], "max": [1, 0.4, 0.25]}],
  "boundaries": {
    "walls": [{"min": [0, 0, 0], "max": [1, 0.4, 1]}],
    "boxes": [{"min": [0.5, 0.1, 0.2], "max": [0.7, 0.3, 0.3], "layers": )" + std::to_string(layers) + R"(, "floating": )" +
           floating + extra + R"(}],
    "method": ")" + method + R"("
  }
})";
}

}  // namespace

TEST_CASE("a floating box: read, written back the same, its mass, centre and inertia from its particles") {
    const clsph::Scene s = clsph::Scene::from_json_text(scene_with(R"({"density": 500, "name": "buoy"})"), "tank.json");
    REQUIRE(s.solids.size() == 1);
    CHECK(s.has_floating());
    CHECK_FALSE(s.has_motion());
    const clsph::Scene back = clsph::Scene::from_json_text(s.to_json(), "back.json");
    CHECK(back.to_json() == s.to_json());
    const auto bodies = clsph::scene::floating_bodies(s);
    REQUIRE(bodies.size() == 1);
    const auto& b = bodies[0];
    CHECK(b.name == "buoy");
    CHECK(b.key == "boundaries.boxes[0]");
    // 5 x 5 x 3 lattice points; the volume is the extent plus dp/2 a side.
    CHECK(b.count == 75u);
    const double mass = 500.0 * 0.25 * 0.25 * 0.15;
    CHECK(b.mass == doctest::Approx(mass).epsilon(1e-12));
    CHECK(b.centre[0] == doctest::Approx(0.6));
    CHECK(b.centre[1] == doctest::Approx(0.2));
    CHECK(b.centre[2] == doctest::Approx(0.25));
    // Point masses m = M / 75 at offsets {-2..2} dp, {-2..2} dp, {-1..1} dp: I_xx = m (sum y^2 + sum z^2).
    const double m = mass / 75.0, dp = 0.05;
    const double sy = 15.0 * 10.0 * dp * dp, sz = 25.0 * 2.0 * dp * dp, sx = 15.0 * 10.0 * dp * dp;
    CHECK(b.inertia[0] == doctest::Approx(m * (sy + sz)));
    CHECK(b.inertia[4] == doctest::Approx(m * (sx + sz)));
    CHECK(b.inertia[8] == doctest::Approx(m * (sx + sy)));
    CHECK(std::abs(b.inertia[1]) < 1e-12);
    // Given: mass, centre and a diagonal inertia are taken as they are.
    const clsph::Scene g = clsph::Scene::from_json_text(
        scene_with(R"({"mass": 2.5, "centre": [0.6, 0.2, 0.22], "inertia": [0.1, 0.2, 0.3]})"), "tank.json");
    const auto gb = clsph::scene::floating_bodies(g);
    CHECK(gb[0].name == "box0");
    CHECK(gb[0].mass == 2.5);
    CHECK(gb[0].centre[2] == 0.22);
    CHECK(gb[0].inertia[4] == 0.2);
    CHECK(gb[0].inertia[1] == 0.0);
    const clsph::Scene gback = clsph::Scene::from_json_text(g.to_json(), "back.json");
    CHECK(gback.to_json() == g.to_json());
}

TEST_CASE("a floating box takes mDBC walls by default, as every scene does; dbc stays selectable") {
    std::string doc = scene_with(R"({"density": 500})");
    doc.erase(doc.find(",\n    \"method\""), std::string(",\n    \"method\": \"dbc\"").size());
    const clsph::Scene def = clsph::Scene::from_json_text(doc, "tank.json");
    CHECK(def.boundary_method == clsph::BoundaryMethod::mdbc);
    CHECK(def.physics.alpha_wall == doctest::Approx(0.3));
    CHECK(def.notes.empty());
    CHECK(clsph::Scene::from_json_text(scene_with(R"({"density": 500})", "", "mdbc"), "tank.json").boundary_method ==
          clsph::BoundaryMethod::mdbc);
    CHECK(clsph::Scene::from_json_text(scene_with(R"({"density": 500})"), "tank.json").boundary_method ==
          clsph::BoundaryMethod::dbc);
}

TEST_CASE("bad floating bodies are errors naming the file and the key") {
    auto error = [](const std::string& floating, const std::string& extra = "", const std::string& method = "dbc", int layers = 0) {
        return error_of([&] { (void)clsph::Scene::from_json_text(scene_with(floating, extra, method, layers), "tank.json"); });
    };
    CHECK(error(R"({"density": 0})").find("tank.json: boundaries.boxes[0].floating.density: must be a finite density > 0") == 0);
    CHECK(error(R"({"density": -3})").find("boundaries.boxes[0].floating.density") != std::string::npos);
    CHECK(error(R"({"mass": -1})").find("boundaries.boxes[0].floating.mass: must be a finite mass > 0") != std::string::npos);
    CHECK(error(R"({})").find("boundaries.boxes[0].floating: needs \"density\"") != std::string::npos);
    CHECK(error(R"({"density": 500, "mass": 2})").find("floating.mass: give density or mass, not both") != std::string::npos);
    CHECK(error(R"({"density": 500, "inertia": [1, 2]})").find("floating.inertia: expected 3 numbers") != std::string::npos);
    CHECK(error(R"({"density": 500, "inertia": [1, -2, 3]})").find("floating.inertia: must be positive definite") != std::string::npos);
    CHECK(error(R"({"density": 500, "inertia": [1, 0.5, 0, 0, 1, 0, 0, 0, 1]})").find("floating.inertia: must be symmetric") != std::string::npos);
    CHECK(error(R"({"density": 500, "name": "a b"})").find("floating.name: \"a b\" is not a usable name") != std::string::npos);
    CHECK(error(R"({"density": 500, "spin": 1})").find("boundaries.boxes[0].floating") != std::string::npos);
    CHECK(error(R"({"density": 500})", R"(, "motion": {"segments": [{"type": "linear", "start": 0, "end": 1, "velocity": [1, 0, 0]}]})")
              .find("boundaries.boxes[0].floating: a floating solid cannot have a prescribed motion too") != std::string::npos);
    // Touching the tank's floor (z = 0, its first layer of particles) at the box's bottom face.
    {
        clsph::Scene t = clsph::Scene::from_json_text(scene_with(R"({"density": 500})"), "tank.json");
        t.solids[0].min[2] = 0.0;
        const std::string e = error_of([&] { t.validate(); });
        CHECK(e.find("boundaries.boxes[0]: touches another solid at (") == 0);
    }
    // A shell (layers > 0) still may not start in the fluid: the fluid would be trapped inside.
    CHECK(error(R"({"density": 500})", "", "dbc", 1).find("overlaps the solid boundaries.boxes[0]") != std::string::npos);
}

TEST_CASE("a floating body's initial velocity and angular velocity: read, written back, checked against its free axes") {
    const clsph::Scene s = clsph::Scene::from_json_text(
        scene_with(R"({"density": 500, "free_translation": [false, false, true], "free_rotation": [false, true, false],
                       "velocity": [0, 0, -0.1], "angular_velocity": [0, 0.5, 0]})"),
        "tank.json");
    CHECK(s.solids[0].floating.velocity == clsph::Vec3{0, 0, -0.1});
    CHECK(s.solids[0].floating.angular_velocity == clsph::Vec3{0, 0.5, 0});
    const auto b = clsph::scene::floating_bodies(s);
    CHECK(b[0].velocity[2] == -0.1);
    CHECK(b[0].angular_velocity[1] == 0.5);
    // Written back (run.json, to_json) and read again the same; a body without them writes neither
    // (its resolved scene, hence a checkpoint's scene hash, as before the keys existed).
    const clsph::Scene back = clsph::Scene::from_json_text(s.to_json(), "back.json");
    CHECK(back.to_json() == s.to_json());
    CHECK(back.solids[0].floating.angular_velocity == clsph::Vec3{0, 0.5, 0});
    const clsph::Scene still = clsph::Scene::from_json_text(scene_with(R"({"density": 500})"), "tank.json");
    CHECK(still.to_json().find("\"angular_velocity\"") == std::string::npos);
    CHECK(still.solids[0].floating.angular_velocity == clsph::Vec3{0, 0, 0});
    CHECK(still.solids[0].floating.velocity == clsph::Vec3{0, 0, 0});

    auto error = [](const std::string& floating) {
        return error_of([&] { (void)clsph::Scene::from_json_text(scene_with(floating), "tank.json"); });
    };
    CHECK(error(R"({"density": 500, "velocity": [0, 1]})").find("tank.json: boundaries.boxes[0].floating.velocity: expected 3 numbers") ==
          0);
    CHECK(error(R"({"density": 500, "angular_velocity": "fast"})").find("boundaries.boxes[0].floating.angular_velocity: expected 3 numbers") !=
          std::string::npos);
    // Along an axis the body may not move on: the integrator would hold it there while it "moved".
    CHECK(error(R"({"density": 500, "free_translation": [true, false, true], "velocity": [0, 0.2, 0]})")
              .find("boundaries.boxes[0].floating.velocity: has 0.2 along y, which free_translation holds fixed") != std::string::npos);
    CHECK(error(R"({"density": 500, "free_rotation": [false, true, false], "angular_velocity": [1, 0, 0]})")
              .find("boundaries.boxes[0].floating.angular_velocity: has 1 along x, which free_rotation holds fixed") != std::string::npos);
    // From code: not finite.
    clsph::Scene t = clsph::Scene::from_json_text(scene_with(R"({"density": 500})"), "tank.json");
    t.solids[0].floating.angular_velocity[2] = std::nan("");
    CHECK(error_of([&] { t.validate(); }).find("boundaries.boxes[0].floating.angular_velocity: expected 3 finite numbers") == 0);
}
