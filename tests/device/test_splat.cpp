// Screen-space fluid rendering (render.method "splat": kernels/splat.cl, kernels/splat_shade.cl,
// host/src/render/splat*.cpp) on every device: a ball of particles splats a disc of its projected
// area, its summed thickness is the particles' volume, its front-most depth the nearest
// particle's; boundary particles are not drawn; one device and three give the same picture; a bad
// render.method is an error that names the key.
#include "clsph/error.hpp"
#include "clsph/render.hpp"
#include "clsph/scene.hpp"
#include "clsph/simulation.hpp"
#include "device/particle_store.hpp"
#include "render/splat.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>
#include <string>

using namespace clsph;

namespace {
constexpr double kPi = 3.14159265358979323846;

double dot3(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
}  // namespace

TEST_SUITE("splat") {
TEST_CASE("a ball of particles splats a disc of its projected area, its volume in thickness, its nearest depth") {
    auto gen = test::rng(3001);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    const double dp = 0.01, R = 0.2;
    const Vec3 centre{0.5 + 0.05 * u(gen), 0.5 + 0.05 * u(gen), 0.5 + 0.05 * u(gen)};
    // A lattice at a random offset, the points within R of the centre; a few boundary particles in
    // front of the ball, which must not be drawn.
    Particles p;
    const Vec3 shift{u(gen) * dp, u(gen) * dp, u(gen) * dp};
    const int n = static_cast<int>(R / dp) + 1;
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                const Vec3 x{centre[0] + shift[0] + i * dp, centre[1] + shift[1] + j * dp, centre[2] + shift[2] + k * dp};
                const double r = std::sqrt((x[0] - centre[0]) * (x[0] - centre[0]) + (x[1] - centre[1]) * (x[1] - centre[1]) +
                                           (x[2] - centre[2]) * (x[2] - centre[2]));
                if (r > R) continue;
                p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::fluid, x, {0, 0, 0}, 1000, 0);
            }
    const std::size_t fluid = p.size();
    CameraView cam;
    cam.width = 480;
    cam.height = 360;
    cam.fov_deg = 30;
    cam.target = centre;
    const double d = 2.0;
    const Vec3 view = {0.6, -0.8, 0.0};  // unit, from the centre to the eye
    cam.eye = {centre[0] + d * view[0], centre[1] + d * view[1], centre[2] + d * view[2]};
    for (int b = 0; b < 50; ++b) {  // boundary particles between the ball and the eye, off its axis
        const double t = 0.3 + 0.01 * b;
        p.push_back(static_cast<std::uint32_t>(p.size()), ParticleType::boundary,
                    {centre[0] + t * view[0], centre[1] + t * view[1], centre[2] + 0.15}, {0, 0, 0}, 1000, 0);
    }
    const double radius = render::kSplatRadius * dp;
    const device::Grid grid(device::Box{{0, 0, 0}, {1, 1, 1}}, 2 * dp);
    // The disc's area: of the convex outline of the particles' projected circles (the centres
    // projected, each circle's radius its sphere's silhouette), from its support function h,
    // area = 1/2 of the integral of h^2 - h'^2 over the angle (lattice effects included).
    const double scale = 0.5 * cam.height / std::tan(0.5 * cam.fov_deg * kPi / 180.0);
    const Vec3 forward{-view[0], -view[1], -view[2]}, right{0.8, 0.6, 0.0}, upv{0, 0, 1};  // forward x up
    constexpr int kAngles = 720;
    std::vector<double> h(kAngles, -1e300);
    for (std::size_t i = 0; i < fluid; ++i) {
        const Vec3 rel{p.position[i][0] - cam.eye[0], p.position[i][1] - cam.eye[1], p.position[i][2] - cam.eye[2]};
        const double z = dot3(rel, forward), x = scale * dot3(rel, right) / z, y = scale * dot3(rel, upv) / z;
        const double rho = scale * radius / std::sqrt(z * z - radius * radius);
        if (x * x + y * y < 0.8 * 0.8 * scale * scale * R * R / (d * d)) continue;  // inside: not on the outline
        for (int k = 0; k < kAngles; ++k) {
            const double a = 2 * kPi * k / kAngles;
            h[static_cast<std::size_t>(k)] = std::max(h[static_cast<std::size_t>(k)], x * std::cos(a) + y * std::sin(a) + rho);
        }
    }
    double area = 0;
    for (int k = 0; k < kAngles; ++k) {
        const double dh = (h[static_cast<std::size_t>((k + 1) % kAngles)] - h[static_cast<std::size_t>(k)]) / (2 * kPi / kAngles);
        area += 0.5 * (h[static_cast<std::size_t>(k)] * h[static_cast<std::size_t>(k)] - dh * dh) * (2 * kPi / kAngles);
    }
    // The nearest particle's front: its depth along the view direction less the radius.
    double nearest = 1e300;
    for (std::size_t i = 0; i < fluid; ++i) {
        const Vec3 rel{p.position[i][0] - cam.eye[0], p.position[i][1] - cam.eye[1], p.position[i][2] - cam.eye[2]};
        nearest = std::min(nearest, -dot3(rel, view) - radius);
    }
    const double volume = static_cast<double>(fluid) * 4.0 / 3.0 * kPi * radius * radius * radius;
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::ParticleStore store(*dev, grid, p.size());
        store.upload(p);
        render::Splatter splatter(*dev, grid);
        const auto im = splatter.draw(cam, store, 0, p.size(), radius);
        REQUIRE(im.depth.size() == std::size_t{cam.width} * cam.height);
        std::size_t covered = 0, stray = 0;
        double front = 1e300, summed = 0;
        for (std::size_t q = 0; q < im.depth.size(); ++q) {
            const bool hit = im.depth[q] != 0xffffffffu;
            covered += hit;
            stray += hit != (im.thickness[q] > 0);  // depth and thickness agree on what was drawn
            if (!hit) continue;
            float z;
            std::memcpy(&z, &im.depth[q], 4);
            front = std::min(front, double{z});
            // A chord through the pixel times its cross-section there: the pixel's solid angle
            // 1 / (scale^2 (1 + u^2 + v^2)^1.5) times the ray's distance squared, d^2 (1 + u^2 + v^2)
            // (the ball is small against its distance).
            const double px = (static_cast<double>(q % cam.width) + 0.5 - 0.5 * cam.width) / scale;
            const double py = (static_cast<double>(q / cam.width) + 0.5 - 0.5 * cam.height) / scale;
            const double footprint = d * d / (scale * scale) / std::sqrt(1 + px * px + py * py);
            summed += footprint * static_cast<double>(im.thickness[q]) * im.unit;
        }
        MESSAGE(covered << " pixels covered, projected area " << area << "; thickness x area " << summed
                        << " m^3, volume " << volume << "; front " << front << " m, nearest " << nearest << " m");
        CHECK(std::abs(static_cast<double>(covered) / area - 1) < 0.03);
        CHECK(stray == 0);
        CHECK(std::abs(summed / volume - 1) < 0.03);
        CHECK(std::abs(front - nearest) <= d / scale);  // within a pixel's depth step
    }
}

TEST_CASE("a run's images reuse their buffers: a frame of another size between two frames changes neither") {
    // The splat pass, the shading and the solids' image keep their buffers from frame to frame
    // (render/frame_cache.hpp): what one frame left there must not show in the next, and a frame
    // of another size must be what a fresh run draws at that size.
    Scene s = test::small_tank(0.1, 0.2);
    SolidBox obstacle;
    obstacle.min = {0.2, 0.03, 0};
    obstacle.max = {0.24, 0.07, 0.04};
    s.solids.push_back(obstacle);
    s.render.method = RenderMethod::splat;
    CameraView big = camera_for(s), small = big;
    big.width = 240;
    big.height = 160;
    small.width = 120;
    small.height = 90;
    // One device, and two where there are two (the second's image merged into the first's buffers).
    for (std::size_t count = 1; count <= std::min<std::size_t>(2, test::devices().size()); ++count) {
        Options o;
        o.devices = test::device_spec(count);
        CAPTURE(o.devices);
        Simulation sim(s, o), fresh(s, o);
        for (int i = 0; i < 5; ++i) {
            sim.step();
            fresh.step();
        }
        const Image first = sim.image(big);
        const Image between = sim.image(small);
        const Image again = sim.image(big);
        const Image small_fresh = fresh.image(small);
        CHECK(first.rgb == again.rgb);
        CHECK(between.rgb == small_fresh.rgb);
        CHECK(between.rgb.size() == std::size_t{3} * small.width * small.height);
    }
}

TEST_CASE("nothing to splat leaves both images empty; a bad render.method names the key") {
    const device::Grid grid(device::Box{{0, 0, 0}, {1, 1, 1}}, 0.1);
    CameraView cam;
    cam.width = 17;
    cam.height = 9;
    cam.eye = {0.5, -2, 0.5};
    cam.target = {0.5, 0.5, 0.5};
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        device::ParticleStore store(*dev, grid, 4);
        render::Splatter splatter(*dev, grid);
        const auto im = splatter.draw(cam, store, 0, 0, 0.01);
        CHECK(std::all_of(im.depth.begin(), im.depth.end(), [](std::uint32_t v) { return v == 0xffffffffu; }));
        CHECK(std::all_of(im.thickness.begin(), im.thickness.end(), [](std::uint32_t v) { return v == 0; }));
    }
    const char* scene = R"({"physics": {"dp": 0.05}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}], "render": {"method": "raytrace"}})";
    try {
        (void)Scene::from_json_text(scene, "bad.json");
        FAIL("a bad render.method was accepted");
    } catch (const SceneError& e) {
        const std::string what = e.what();
        CHECK_MESSAGE(what.find("render.method") != std::string::npos, what);
        CHECK_MESSAGE(what.find("\"splat\"") != std::string::npos, what);
    }
}
}

// Three devices of one implementation (CTest: POCL_DEVICES="pthread pthread pthread").
TEST_SUITE("multi_bitwise") {
TEST_CASE("splats: the same scene on one device and on three gives the same image within a few pixels") {
    REQUIRE(test::devices().size() >= 3);
    Scene s = test::small_tank(0.1, 0.2);
    SolidBox obstacle;
    obstacle.min = {0.2, 0.03, 0};
    obstacle.max = {0.24, 0.07, 0.04};
    s.solids.push_back(obstacle);
    s.render.width = 400;
    s.render.height = 300;
    s.render.method = RenderMethod::splat;
    auto image_on = [&](std::size_t count) {
        Options o;
        o.devices = test::device_spec(count);
        Simulation sim(s, o);
        for (int i = 0; i < 10; ++i) sim.step();  // the particles moved and migrated a little
        Image im = sim.image(camera_for(s));
        if (const char* dir = std::getenv("CLSPH_TEST_IMAGES"))
            write_png(std::string(dir) + "/splat_" + std::to_string(count) + ".png", im);
        return im;
    };
    const Image one = image_on(1), three = image_on(3);
    REQUIRE(one.rgb.size() == three.rgb.size());
    std::size_t differ = 0;
    for (std::size_t q = 0; q < one.rgb.size() / 3; ++q) {
        bool same = true;
        for (std::size_t c = 0; c < 3; ++c) same = same && std::abs(int(one.rgb[3 * q + c]) - int(three.rgb[3 * q + c])) <= 2;
        differ += same ? 0 : 1;
    }
    MESSAGE(differ << " pixels differ between one device and three");
    CHECK(differ <= 10);
}
}
