// Images rendered by the devices (kernels/render.cl, host/src/render/): a sphere's silhouette
// against its exact projected area on every device, PNG files read back, the default camera
// framing the domain, and the same image from one device and from three.
#include "clsph/error.hpp"
#include "clsph/render.hpp"
#include "clsph/simulation.hpp"
#include "render/renderer.hpp"
#include "render/scene_image.hpp"
#include "surface/marching_cubes.hpp"
#include "support/image.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

using namespace clsph;

namespace {
constexpr double kPi = 3.14159265358979323846;

TriangleMesh sphere_mesh(double radius, const Vec3& centre, std::uint32_t n) {
    surface::SampleGrid g;
    g.points = {n, n, n};
    const double extent = 1.3 * radius;
    g.spacing = 2 * extent / (n - 1);
    for (int k = 0; k < 3; ++k) g.origin[static_cast<std::size_t>(k)] = centre[static_cast<std::size_t>(k)] - extent;
    std::vector<float> f(g.samples());
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i) {
                const double x = g.origin[0] + i * g.spacing - centre[0], y = g.origin[1] + j * g.spacing - centre[1],
                             z = g.origin[2] + k * g.spacing - centre[2];
                f[i + n * (j + n * k)] = static_cast<float>(radius - std::sqrt(x * x + y * y + z * z));
            }
    return surface::marching_cubes_reference(f, g, 0.0f);
}
}  // namespace

TEST_SUITE("render") {
TEST_CASE("a moved box is drawn where it now is: turned and moved, it covers what a box built there covers") {
    // Images draw moving and floating boxes at their pose (render::solids_layer): a box turned by a
    // quarter turn about z through its centre and moved by T must cover the pixels of the box
    // built at its new place (with its x and y extents swapped), and not those of the box at rest.
    auto gen = test::rng(1950);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    SolidBox rest;
    rest.min = {0.2 + u(gen), 0.4 + u(gen), 0.1};
    rest.max = {rest.min[0] + 0.3, rest.min[1] + 0.1, 0.3};
    const Vec3 c{0.5 * (rest.min[0] + rest.max[0]), 0.5 * (rest.min[1] + rest.max[1]), 0.2};
    const Vec3 shift{0.6 + u(gen), -0.3, 0.05};
    scene::RigidPose pose;  // x -> R (x - c) + c + shift, R a quarter turn about z
    pose.R = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    pose.T = {c[0] + c[1] + shift[0], c[1] - c[0] + shift[1], shift[2]};
    SolidBox there;  // the same box built at its new place
    const Vec3 nc{c[0] + shift[0], c[1] + shift[1], c[2] + shift[2]};
    there.min = {nc[0] - 0.05, nc[1] - 0.15, 0.1 + shift[2]};
    there.max = {nc[0] + 0.05, nc[1] + 0.15, 0.3 + shift[2]};
    Scene moved_scene, there_scene;
    moved_scene.solids = {rest};
    there_scene.solids = {there};
    CameraView cam;
    cam.width = 320;
    cam.height = 240;
    cam.eye = {0.7, -2.0, 1.2};
    cam.target = {0.7, 0.3, 0.2};
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        render::FrameCache cache;
        render::UploadedLayer a, b, r;
        const auto moved = cache.renderer(*dev).draw(cam, {render::solids_layer(cache, *dev, moved_scene, {pose}, a)});
        render::FrameCache other;
        const auto built = other.renderer(*dev).draw(cam, {render::solids_layer(other, *dev, there_scene, {}, b)});
        render::FrameCache third;
        const auto at_rest = third.renderer(*dev).draw(cam, {render::solids_layer(third, *dev, moved_scene, {scene::RigidPose{}}, r)});
        std::size_t covered = 0, differ = 0, rest_differ = 0;
        for (std::size_t p = 0; p < moved.depth.size(); ++p) {
            const bool m = moved.depth[p] != 0xffffffffu, t = built.depth[p] != 0xffffffffu, z = at_rest.depth[p] != 0xffffffffu;
            covered += t;
            differ += m != t;
            rest_differ += z != t;
        }
        MESSAGE(covered << " pixels covered by the box built there; " << differ << " differ from the moved box, " << rest_differ
                        << " from the box at rest");
        REQUIRE(covered > 500);
        CHECK(differ <= covered / 100);
        CHECK(rest_differ > covered / 2);
    }
}

TEST_CASE("a sphere's silhouette covers pi r^2 pixels within 2 % on every device") {
    auto gen = test::rng(1900);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    const double R = 0.5;
    const Vec3 centre{u(gen), u(gen), u(gen)};
    const TriangleMesh sphere = sphere_mesh(R, centre, 120);
    CameraView cam;
    cam.width = 640;
    cam.height = 480;
    cam.fov_deg = 30;
    cam.target = centre;
    const double d = 3.0;
    cam.eye = {centre[0] + d * 0.6, centre[1] - d * 0.8, centre[2]};
    cam.up = {0, 0, 1};
    // The silhouette of a sphere seen from distance d is a circle of angular radius asin(R / d).
    const double scale = 0.5 * cam.height / std::tan(0.5 * cam.fov_deg * kPi / 180.0);
    const double r_px = scale * std::tan(std::asin(R / d));
    const double expected = kPi * r_px * r_px;
    for (auto* dev : test::devices()) {
        CAPTURE(dev->label());
        render::Renderer r(*dev);
        render::Layer layer{&sphere, {}, {0.3f, 0.5f, 0.9f}};
        for (std::uint32_t t = 0; t < sphere.triangles.size(); ++t) layer.triangles.push_back(t);
        const auto im = r.draw(cam, {layer});
        std::size_t covered = 0, coloured = 0;
        for (std::size_t p = 0; p < im.depth.size(); ++p) {
            covered += im.depth[p] != 0xffffffffu;
            coloured += im.colour[p] != 0;
        }
        MESSAGE(covered << " pixels covered, pi r^2 = " << expected);
        CHECK(std::abs(static_cast<double>(covered) / expected - 1) < 0.02);
        CHECK(coloured == covered);  // every covered pixel got its colour in the second pass
    }
}

TEST_CASE("a PNG reads back as written; a bad image is refused") {
    Image im;
    im.width = 37;
    im.height = 11;
    auto gen = test::rng(1901);
    for (std::size_t i = 0; i < std::size_t{3} * im.width * im.height; ++i) im.rgb.push_back(static_cast<std::uint8_t>(gen()));
    const std::string dir = std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp";
    const std::string path = dir + "/clsph_test_" + std::to_string(test::seed()) + ".png";
    write_png(path, im);
    const Image back = read_png(path);
    std::remove(path.c_str());
    CHECK(back.width == im.width);
    CHECK(back.height == im.height);
    CHECK(back.rgb == im.rgb);
    Image bad;
    bad.width = 4;
    bad.height = 4;
    CHECK_THROWS_AS(write_png(path, bad), clsph::Error);
    CHECK_THROWS_AS(read_png(dir + "/clsph_no_such_file.png"), clsph::Error);
}

namespace {
// Where the eight corners of [lo, hi] land in the image of `c`: min and max pixel x and y.
std::array<double, 4> projected(const CameraView& c, const Vec3& lo, const Vec3& hi) {
    const double scale = 0.5 * c.height / std::tan(0.5 * c.fov_deg * kPi / 180.0);
    auto unit = [](Vec3 v) {
        const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        return Vec3{v[0] / l, v[1] / l, v[2] / l};
    };
    const Vec3 f = unit({c.target[0] - c.eye[0], c.target[1] - c.eye[1], c.target[2] - c.eye[2]});
    const Vec3 r = unit({f[1] * c.up[2] - f[2] * c.up[1], f[2] * c.up[0] - f[0] * c.up[2], f[0] * c.up[1] - f[1] * c.up[0]});
    const Vec3 up{r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
    for (int corner = 0; corner < 8; ++corner) {
        Vec3 p{};
        for (int k = 0; k < 3; ++k) p[static_cast<std::size_t>(k)] = (corner >> k) & 1 ? hi[static_cast<std::size_t>(k)] : lo[static_cast<std::size_t>(k)];
        const Vec3 d{p[0] - c.eye[0], p[1] - c.eye[1], p[2] - c.eye[2]};
        const double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
        REQUIRE(z > 0);
        const double x = 0.5 * c.width + scale * (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / z;
        const double y = 0.5 * c.height - scale * (d[0] * up[0] + d[1] * up[1] + d[2] * up[2]) / z;
        box = {std::min(box[0], x), std::max(box[1], x), std::min(box[2], y), std::max(box[3], y)};
    }
    return box;
}
}  // namespace

TEST_CASE("the default camera frames the subject: a tank in a large domain fills the picture") {
    Scene s;
    s.domain.min = {-1, -1, -1};
    s.domain.max = {4, 3, 3};
    BoxWalls tank;
    tank.min = {0, 0, 0};
    tank.max = {1.6, 0.6, 0.5};
    s.walls.push_back(tank);
    FluidBlock water;
    water.min = {0, 0, 0};
    water.max = {0.4, 0.6, 0.4};
    s.fluids.push_back(water);
    const CameraView c = camera_for(s);
    const auto box = projected(c, tank.min, tank.max);
    MESSAGE("the tank spans x " << box[0] << ".." << box[1] << ", y " << box[2] << ".." << box[3] << " of " << c.width << " x " << c.height);
    CHECK(box[0] >= 0);
    CHECK(box[1] < c.width);
    CHECK(box[2] >= 0);
    CHECK(box[3] < c.height);
    // Fitted: it reaches within 5 % of an edge of the picture, and spans most of its width.
    CHECK((box[0] < 0.05 * c.width || box[1] > 0.95 * c.width || box[2] < 0.05 * c.height || box[3] > 0.95 * c.height));
    CHECK(box[1] - box[0] > 0.6 * c.width);
}

TEST_CASE("the default camera of an empty scene frames the domain: every corner of the domain is in the image") {
    Scene s;
    s.domain.min = {-0.3, 0.1, 0};
    s.domain.max = {2.5, 0.9, 1.2};
    const CameraView c = camera_for(s);
    CHECK(c.width >= 1280);
    CHECK(c.height >= 720);
    // Every corner in the image: the box of their projections is.
    const auto box = projected(c, s.domain.min, s.domain.max);
    CHECK(box[0] >= 0);
    CHECK(box[1] < c.width);
    CHECK(box[2] >= 0);
    CHECK(box[3] < c.height);
}
}

// Three devices of one implementation (CTest: POCL_DEVICES="pthread pthread pthread").
TEST_SUITE("multi_bitwise") {
TEST_CASE("the same scene rendered on one device and on three gives the same image within a few pixels") {
    REQUIRE(test::devices().size() >= 3);
    Scene s = test::small_tank(0.1, 0.2);
    SolidBox obstacle;
    obstacle.min = {0.2, 0.03, 0};
    obstacle.max = {0.24, 0.07, 0.04};
    s.solids.push_back(obstacle);
    s.render.width = 400;
    s.render.height = 300;
    s.render.surface_spacing = 0.5 * s.physics.dp;  // image() samples the surface as surface() does
    auto image_on = [&](std::size_t count) {
        Options o;
        o.devices = test::device_spec(count);
        Simulation sim(s, o);
        for (int i = 0; i < 30; ++i) sim.step();
        // From the downloaded mesh and straight from the devices' memory: the same picture.
        const Image from_mesh = sim.render(sim.surface(), camera_for(s)), direct = sim.image(camera_for(s));
        REQUIRE(from_mesh.rgb.size() == direct.rgb.size());
        std::size_t apart = 0;
        for (std::size_t b = 0; b < direct.rgb.size(); ++b) apart += std::abs(int(from_mesh.rgb[b]) - int(direct.rgb[b])) > 2;
        // On one device the same bytes; on several, a vertex where two devices' blocks meet is
        // each device's own (its normal from its block's one-sided differences), so a few pixels
        // along the cuts shade differently.
        MESSAGE(count << " devices: " << apart << " bytes differ between render(surface()) and image()");
        if (const char* dir = std::getenv("CLSPH_TEST_IMAGES")) {
            write_png(std::string(dir) + "/from_mesh_" + std::to_string(count) + ".png", from_mesh);
            write_png(std::string(dir) + "/direct_" + std::to_string(count) + ".png", direct);
        }
        CHECK(apart <= (count == 1 ? 0u : direct.rgb.size() / 3 / 1000));
        return from_mesh;
    };
    const Image one = image_on(1), three = image_on(3);
    REQUIRE(one.rgb.size() == three.rgb.size());
    std::size_t differ = 0;
    for (std::size_t p = 0; p < one.rgb.size() / 3; ++p) {
        bool same = true;
        for (std::size_t c = 0; c < 3; ++c) same = same && std::abs(int(one.rgb[3 * p + c]) - int(three.rgb[3 * p + c])) <= 2;
        differ += same ? 0 : 1;
    }
    const std::size_t drawn = test_image::drawn_pixels(one);  // against the image's own background
    MESSAGE(drawn << " pixels drawn, " << differ << " differ between one device and three");
    CHECK(drawn > 5000);
    CHECK(differ <= 10);
}
}
