// The free surface from the command line: `clsph run --surface` writes a mesh per frame listed in
// surface.pvd at the frames' times, and `clsph surface DIR` meshes a finished run's frames again.
#include "support.hpp"

#include <clsph/mesh.hpp>
#include <clsph/render.hpp>

#include <cstdio>
#include <cstdlib>
#include <iterator>

#include <doctest/doctest.h>

using namespace cli_test;

namespace {
// Closed but at the periodic faces: every directed edge has its reverse, unless both its ends lie
// on the slice's periodic faces (y = 0 or y = the period, within a sample spacing): the dam break
// is a slice periodic in y, and its surface is one period, open there.
bool closed(const clsph::TriangleMesh& m, double period = 0.1898, double spacing = 0.0073) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& t : m.triangles)
        for (int e = 0; e < 3; ++e) edges.push_back({t[e], t[(e + 1) % 3]});
    std::sort(edges.begin(), edges.end());
    auto on_face = [&](std::uint32_t v) {
        const double y = m.positions[v][1];
        return y < spacing || y > period - spacing;
    };
    for (const auto& [a, b] : edges)
        if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a)) && !(on_face(a) && on_face(b))) return false;
    return !edges.empty();
}
}  // namespace

TEST_CASE("clsph run --surface and clsph surface: a closed mesh per frame, listed at the frames' times") {
    const std::string out = work_dir("surface");
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", "0.01", "--every", "0.005", "--surface-ply", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    const auto surfaces = clsph::read_pvd(out + "/surface.pvd");
    REQUIRE(surfaces.size() == frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CHECK(surfaces[i].time == frames[i].time);
        CHECK(fs::file_size(out + "/" + surfaces[i].file) > 1000);
        const auto ply = out + "/" + surfaces[i].file.substr(0, surfaces[i].file.size() - 4) + ".ply";
        const auto mesh = clsph::read_ply(ply);
        CHECK(mesh.triangles.size() > 100);
        CHECK(closed(mesh));
    }
    // Afterwards, from the frames on disk: the same number of surfaces at the same times.
    fs::remove(out + "/surface.pvd");
    code = run({"surface", out, "--ply"}, log);
    INFO(log);
    REQUIRE(code == 0);
    const auto again = clsph::read_pvd(out + "/surface.pvd");
    REQUIRE(again.size() == frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) CHECK(again[i].time == frames[i].time);
    CHECK(closed(clsph::read_ply(out + "/surface_00000.ply")));
    // Not an output directory: a clear error, exit 1.
    code = run({"surface", out + "/no_such_dir"}, log);
    CHECK(code == 1);
    CHECK(log.find("run.json") != std::string::npos);
}

TEST_CASE("clsph run --render and clsph render: a PNG per surface, a note or a video") {
    const std::string out = work_dir("render");
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", "0.01", "--every", "0.005", "--render", "--video", "--set",
                                                "render.size=[320,180]", "--out", out}}),
                   log);
    INFO(log);
    REQUIRE(code == 0);
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    for (std::size_t i = 0; i < frames.size(); ++i) {
        char name[48];  // room for any size_t: no -Wformat-truncation
        std::snprintf(name, sizeof name, "/render_%05zu.png", i);
        const clsph::Image im = clsph::read_png(out + name);
        CHECK(im.width == 320);
        CHECK(im.height == 180);
        std::size_t drawn = 0;  // pixels other than the background
        for (std::size_t p = 0; p < im.rgb.size() / 3; ++p) drawn += im.rgb[3 * p] != 246 || im.rgb[3 * p + 2] != 246;
        CHECK(drawn > 500);
    }
    const bool has_ffmpeg = std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
    if (has_ffmpeg)
        CHECK(fs::file_size(out + "/render.mp4") > 1000);
    else
        CHECK(log.find("ffmpeg is not installed") != std::string::npos);
    fs::remove(out + "/render_00000.png");
    code = run({"render", out}, log);
    CHECK(code == 0);
    CHECK(clsph::read_png(out + "/render_00000.png").width == 320);
}

TEST_CASE("clsph run --render --render-method splat: a PNG per frame, no surface; a bad method is refused") {
    const std::string out = work_dir("render_splat");
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", "0.01", "--every", "0.005", "--render", "--render-method",
                                                "splat", "--set", "render.size=[320,180]", "--out", out}}),
                   log);
    INFO(log);
    REQUIRE(code == 0);
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(!frames.empty());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        char name[48];
        std::snprintf(name, sizeof name, "/render_%05zu.png", i);
        const clsph::Image im = clsph::read_png(out + name);
        CHECK(im.width == 320);
        CHECK(im.height == 180);
    }
    CHECK(!fs::exists(out + "/surface_00000.vtp"));  // splats need no mesh
    CHECK(!fs::exists(out + "/surface.pvd"));
    // The method is recorded with the scene in run.json.
    std::ifstream record(out + "/run.json");
    const std::string text((std::istreambuf_iterator<char>(record)), std::istreambuf_iterator<char>());
    CHECK(text.find("\"method\": \"splat\"") != std::string::npos);
    code = run(args({{"run", scene}, tiny, {"--until", "0.01", "--render-method", "mesh", "--out", out + "_bad"}}), log);
    CHECK(code != 0);
    CHECK(log.find("--render-method") != std::string::npos);
}
