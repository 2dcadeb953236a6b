// Open boundaries in scene files (docs/scenes.md, inlets and outlets): the keys read, round-trip
// through to_json, and every bad value is an error naming its key; the inlets' feed makes layers
// with fresh ids at the times the docs give.
#include "scene/open_boundaries.hpp"
#include "support.hpp"

#include <clsph/scene.hpp>
#include <clsph/scene_io.hpp>

#include <doctest/doctest.h>

#include <set>
#include <string>

using scene_test::error_of;
using scene_test::source_path;

namespace {

// A channel at dp 0.02 with one inlet and one outlet; `inlet` and `outlet` replace their objects.
std::string channel(const std::string& inlet = R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0]})",
                    const std::string& outlet = R"({"face": "x+"})", const std::string& extra = "") {
    return R"({"physics": {"dp": 0.02)" + extra + R"(}, "domain": {"min": [0, -0.06, -0.06], "max": [1, 0.16, 0.2]},
               "fluid": [{"min": [0.08, 0, 0], "max": [0.98, 0.1, 0.06]}],
               "boundaries": {"walls": [{"min": [0, 0, 0], "max": [0.98, 0.1, 0.2], "faces": ["y-", "y+", "z-"]}]},
               "inlets": [)" + inlet + R"(], "outlets": [)" + outlet + "]}";
}

std::string error_in(const std::string& text) {
    return error_of([&] { (void)clsph::Scene::from_json_text(text, "channel.json"); });
}

}  // namespace

TEST_CASE("inlets and outlets: read, validated, written back") {
    const clsph::Scene s = clsph::Scene::from_json_text(channel(), "channel.json");
    REQUIRE(s.inlets.size() == 1);
    CHECK(s.inlets[0].velocity[0] == 0.5);
    CHECK(!s.inlets[0].surface);
    REQUIRE(s.outlets.size() == 1);
    CHECK(s.outlets[0].axis == 0);
    CHECK(s.outlets[0].upper);
    const clsph::Scene back = clsph::Scene::from_json_text(s.to_json(), "back.json");
    CHECK(back.to_json() == s.to_json());
    // A scene without them writes neither key (closed scenes' documents and hashes unchanged).
    const clsph::Scene closed = clsph::Scene::from_file(source_path("scenes/dam_break.json"));
    CHECK(closed.to_json().find("inlets") == std::string::npos);
}

TEST_CASE("bad inlets and outlets are errors naming the key") {
    auto has = [](const std::string& e, const std::string& what) {
        INFO(e);
        CHECK(e.find(what) != std::string::npos);
    };
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0.1, 0]})")),
        "inlets[0].velocity: must be along one axis");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0, 0, 0]})")),
        "inlets[0].velocity");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06]})")), "inlets[0].velocity");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.01, 0.08, 0.06], "velocity": [0.5, 0, 0]})")),
        "inlets[0].max: the box must be at least dp");
    has(error_in(channel(R"({"min": [-0.5, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0]})")),
        "inlets[0].max: the box must lie inside the domain");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0], "speed": 1})")),
        "speed");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0], "surface": "top"})")),
        "inlets[0].surface");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0]})", R"({"face": "x"})")),
        "outlets[0].face");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0]})", R"({})")),
        "outlets[0].face");
    has(error_in(channel(R"({"min": [0, 0.02, 0.02], "max": [0.08, 0.08, 0.06], "velocity": [0.5, 0, 0]})", R"({"face": "x+"})",
                         R"(, "integrator": "symplectic")")),
        "inlets[0]: inlets need physics.integrator \"leapfrog\"");
    has(error_in(R"({"physics": {"dp": 0.02}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
                    "fluid": [{"min": [0.1, 0.1, 0.1], "max": [0.5, 0.5, 0.5]}], "inlets": {"min": [0, 0, 0]}})"),
        "inlets");
}

TEST_CASE("an inlet's feed: layers at the times and places the docs give, fresh ids in order") {
    const clsph::Scene s = clsph::Scene::from_json_text(channel(), "channel.json");
    const std::uint64_t first = 1000;
    clsph::scene::InletFeed feed(s, first);
    // The cross-section: y 0.02 .. 0.08, z 0.02 .. 0.06 on the lattice (4 x 3); 4 layers in the box.
    CHECK(feed.layer_particles() == 12);
    CHECK(feed.buffer_particles() == 48);
    const clsph::Particles start = feed.due(0.0);
    CHECK(start.size() == 48);
    std::set<std::uint32_t> ids(start.id.begin(), start.id.end());
    CHECK(ids.size() == 48);
    CHECK(*ids.begin() == first);
    CHECK(*ids.rbegin() == first + 47);
    for (const auto& x : start.position) CHECK((x[0] >= 0.0 && x[0] < 0.08 - 1e-12));
    CHECK(feed.due(0.039).size() == 0);  // 0.5 m/s: the next layer once the buffer moved 0.02 m
    const clsph::Particles next = feed.due(0.041);
    REQUIRE(next.size() == 12);
    CHECK(next.id.front() == first + 48);
    CHECK(next.position.front()[0] == doctest::Approx(0.5 * 0.041 - 0.02));
    CHECK(feed.state().next_id == first + 60);
    CHECK(feed.state().last_layer == std::vector<std::int64_t>{1});
    // Resumed from that state, the same particles follow.
    clsph::scene::InletFeed again(s, 0);
    again.restore(feed.state());
    const clsph::Particles a = feed.due(0.2), b = again.due(0.2);
    CHECK(a.id == b.id);
    CHECK(a.position == b.position);
    CHECK(a.size() == 12 * 4);  // layers 2 .. 5
    // The memory plan's count: the scene's, the buffer, and the layers of the domain's length.
    CHECK(clsph::scene::planned_with_inlets(s, 5000) == 5000 + 48 + 12 * 51);
}
