// The free surface from the command line: `clsph run --surface` writes a mesh per frame listed in
// surface.pvd at the frames' times, and `clsph surface DIR` meshes a finished run's frames again.
#include "support.hpp"
#include "../support/image.hpp"

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

std::string numbered(const std::string& prefix, std::size_t i, const std::string& extension) {
    char name[48];  // room for any size_t: no -Wformat-truncation
    std::snprintf(name, sizeof name, "%s_%05zu%s", prefix.c_str(), i, extension.c_str());
    return name;
}

// The times --until/--every imply: a frame at t = 0 and at every multiple of `every` to `until`.
void check_frame_times(const std::vector<clsph::PvdEntry>& frames, double every) {
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CAPTURE(i);
        CHECK(near(frames[i].time, every * static_cast<double>(i)));
    }
}
}  // namespace

TEST_CASE("clsph run --surface and clsph surface: a closed mesh per frame, listed at the frames' times") {
    const std::string out = work_dir("surface");
    const std::string until = "0.01", every = "0.005";
    const std::size_t expected = frames_implied(std::stod(until), std::stod(every));
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", until, "--every", every, "--surface-ply", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    // Every frame the arguments imply, at its time, on disk; a surface (VTP and PLY) for each.
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(frames.size() == expected);
    check_frame_times(frames, std::stod(every));
    for (const auto& f : frames) CHECK_MESSAGE(fs::exists(out + "/" + f.file), f.file);
    const auto surfaces = clsph::read_pvd(out + "/surface.pvd");
    REQUIRE(surfaces.size() == expected);
    CHECK(count_files(out, "surface_", ".vtp") == expected);
    CHECK(count_files(out, "surface_", ".ply") == expected);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CAPTURE(i);
        CHECK(surfaces[i].time == frames[i].time);
        REQUIRE_MESSAGE(fs::exists(out + "/" + surfaces[i].file), surfaces[i].file);
        CHECK(fs::file_size(out + "/" + surfaces[i].file) > 1000);
        const auto ply = out + "/" + fs::path(surfaces[i].file).replace_extension(".ply").string();
        REQUIRE_MESSAGE(fs::exists(ply), ply);
        const auto mesh = clsph::read_ply(ply);
        CHECK(mesh.triangles.size() > 100);
        CHECK(closed(mesh));
    }
    // Afterwards, from the frames on disk (the run's surfaces removed first, so that none of them
    // passes for one meshed again): the same number of surfaces at the same times.
    for (const auto& e : std::vector<fs::directory_entry>(fs::directory_iterator(out), fs::directory_iterator()))
        if (e.path().filename().string().rfind("surface", 0) == 0) fs::remove(e.path());
    REQUIRE(count_files(out, "surface", ".pvd") == 0);
    code = run({"surface", out, "--ply"}, log);
    INFO(log);
    REQUIRE(code == 0);
    const auto again = clsph::read_pvd(out + "/surface.pvd");
    REQUIRE(again.size() == expected);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CAPTURE(i);
        CHECK(again[i].time == frames[i].time);
        CHECK_MESSAGE(fs::exists(out + "/" + again[i].file), again[i].file);
        const std::string ply = out + "/" + numbered("surface", i, ".ply");
        REQUIRE_MESSAGE(fs::exists(ply), ply);
        CHECK(closed(clsph::read_ply(ply)));
    }
    // Not an output directory: a clear error, exit 1.
    code = run({"surface", out + "/no_such_dir"}, log);
    CHECK(code == 1);
    CHECK(log.find("run.json") != std::string::npos);
}

TEST_CASE("clsph run --render and clsph render: a PNG per surface, a note or a video") {
    const std::string out = work_dir("render");
    const std::string until = "0.01", every = "0.005";
    const std::size_t expected = frames_implied(std::stod(until), std::stod(every));
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", until, "--every", every, "--render", "--video", "--set",
                                                "render.size=[320,180]", "--out", out}}),
                   log);
    INFO(log);
    REQUIRE(code == 0);
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(frames.size() == expected);
    check_frame_times(frames, std::stod(every));
    CHECK(clsph::read_pvd(out + "/surface.pvd").size() == expected);
    CHECK(count_files(out, "render_", ".png") == expected);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CAPTURE(i);
        const std::string png = out + "/" + numbered("render", i, ".png");
        REQUIRE_MESSAGE(fs::exists(png), png);
        const clsph::Image im = clsph::read_png(png);
        CHECK(im.width == 320);
        CHECK(im.height == 180);
        CHECK(test_image::drawn_pixels(im) > 500);
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
    const std::string until = "0.01", every = "0.005";
    const std::size_t expected = frames_implied(std::stod(until), std::stod(every));
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--until", until, "--every", every, "--render", "--render-method",
                                                "splat", "--set", "render.size=[320,180]", "--out", out}}),
                   log);
    INFO(log);
    REQUIRE(code == 0);
    const auto frames = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(frames.size() == expected);
    check_frame_times(frames, std::stod(every));
    CHECK(count_files(out, "render_", ".png") == expected);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CAPTURE(i);
        const std::string png = out + "/" + numbered("render", i, ".png");
        REQUIRE_MESSAGE(fs::exists(png), png);
        const clsph::Image im = clsph::read_png(png);
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
