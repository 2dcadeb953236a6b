// Images coloured by a particle field (ImageStyle by_speed, by_pressure; kernels/render_field.cl,
// the field sums of kernels/splat.cl): a block of water given a known velocity field, u = x / L
// along x, seen face on. At every pixel of its front face the colour must be the colour map's at
// the speed there (computed here, on the host, from the ray's intersection with the face: matched
// by hue, since the shading scales the colour), for both render methods; at rest the picture is
// one colour; the range found on the devices is the particles' own (least and greatest speed and
// pressure, computed on the host from the downloaded particles).
#include "clsph/render.hpp"
#include "clsph/simulation.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

using namespace clsph;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLength = 0.3;  // the block's length along x (m)

Scene block_scene(RenderMethod method) {
    Scene s = test::small_tank(kLength, 0.1);  // water filling the tank's length, 0.1 m deep
    s.render.method = method;
    s.render.width = 480;
    s.render.height = 200;
    return s;
}

// Face on: from -y, level with the middle of the block's front face.
CameraView face_on() {
    CameraView c;
    c.width = 480;
    c.height = 200;
    c.fov_deg = 20;
    c.target = {0.5 * kLength, 0.0, 0.05};
    c.eye = {0.5 * kLength, -1.2, 0.05};
    c.up = {0, 0, 1};
    return c;
}

// The particles of the scene with fluid velocity u(x) = speed_at(x) along x.
Particles moving(const Scene& s, const Options& o, double top_speed) {
    Simulation sim(s, o);
    Particles p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.type[i] == ParticleType::fluid)
            p.velocity[i] = {static_cast<float>(top_speed * p.position[i][0] / kLength), 0.0f, 0.0f};
    return p;
}

// The t of the colour map whose colour points the way `rgb` does (the shading scales a colour).
double hue_t(const std::uint8_t* rgb) {
    const double l = std::sqrt(double(rgb[0]) * rgb[0] + double(rgb[1]) * rgb[1] + double(rgb[2]) * rgb[2]);
    double best = -1, best_cos = -2;
    for (int k = 0; k <= 400; ++k) {
        const double t = k / 400.0;
        const auto c = field_colour(t);
        const double lc = std::sqrt(double(c[0]) * c[0] + double(c[1]) * c[1] + double(c[2]) * c[2]);
        const double cosine = (rgb[0] * c[0] + rgb[1] * c[1] + rgb[2] * c[2]) / (l * lc);
        if (cosine > best_cos) {
            best_cos = cosine;
            best = t;
        }
    }
    return best;
}

// For each pixel well inside the block's front face (x within [0.15 L, 0.85 L], z within
// [0.02, 0.08] m on the plane y = y_face): the world x there.
struct FacePixel {
    std::size_t index;
    double x;
};
std::vector<FacePixel> face_pixels(const CameraView& c, double y_face) {
    const double scale = 0.5 * c.height / std::tan(0.5 * c.fov_deg * kPi / 180.0);
    std::vector<FacePixel> out;
    // The camera looks along +y with up +z, so right is +x: the ray of pixel (i, j) is
    // (u, 1, v) with u = (i + 0.5 - cx) / scale, v = (cy - j - 0.5) / scale.
    const double distance = y_face - c.eye[1];
    for (std::uint32_t j = 0; j < c.height; ++j)
        for (std::uint32_t i = 0; i < c.width; ++i) {
            const double u = (i + 0.5 - 0.5 * c.width) / scale, v = (0.5 * c.height - j - 0.5) / scale;
            const double x = c.eye[0] + u * distance, z = c.eye[2] + v * distance;
            if (x > 0.15 * kLength && x < 0.85 * kLength && z > 0.02 && z < 0.08)
                out.push_back({std::size_t{j} * c.width + i, x});
        }
    return out;
}

}  // namespace

TEST_SUITE("render") {
TEST_CASE("coloured by speed: the colour of the block's face follows a known velocity field, both render methods") {
    Options o;
    o.devices = test::device_spec(1);
    for (const auto method : {RenderMethod::surface, RenderMethod::splat}) {
        const std::string name = method == RenderMethod::surface ? "surface" : "splat";
        CAPTURE(name);
        const Scene s = block_scene(method);
        Simulation sim(s, moving(s, o, 1.0), o);
        ImageStyle style;
        style.surface = SurfaceColour::by_speed;
        style.range_min = 0;
        style.range_max = 1.0;
        const CameraView cam = face_on();
        const Image coloured = sim.image(cam, style), plain = sim.image(cam);
        CHECK(coloured.range[0] == 0.0);
        CHECK(coloured.range[1] == 1.0);
        CHECK(std::isnan(plain.range[0]));
        // The face: the first layer of particles sits at dp / 2, its surface about half a spacing
        // in front of it (the plane y = 0 is near enough for which x a pixel sees).
        const auto face = face_pixels(cam, 0.0);
        REQUIRE(face.size() > 2000);
        std::vector<double> errors;
        std::size_t recoloured = 0;
        for (const auto& f : face) {
            const double expected = std::clamp(f.x / kLength, 0.0, 1.0);
            errors.push_back(std::abs(hue_t(&coloured.rgb[3 * f.index]) - expected));
            int d = 0;
            for (std::size_t k = 0; k < 3; ++k)
                d = std::max(d, std::abs(int(coloured.rgb[3 * f.index + k]) - int(plain.rgb[3 * f.index + k])));
            recoloured += d > 24;
        }
        std::sort(errors.begin(), errors.end());
        const double median = errors[errors.size() / 2], p90 = errors[errors.size() * 9 / 10];
        MESSAGE(face.size() << " face pixels: |t - x / L| median " << median << ", 90th percentile " << p90 << "; "
                            << recoloured << " differ from the uniform image");
        CHECK(median < 0.06);
        CHECK(p90 < 0.15);
        // Where the water moves the picture is another than the uniform one (the slowest end,
        // near x = 0, may share the uniform blue's hue: most of the face differs, not all).
        CHECK(recoloured > face.size() / 2);
    }
}

TEST_CASE("coloured by speed at rest: one colour; the automatic ranges are the particles' own") {
    Options o;
    o.devices = test::device_spec(1);
    for (const auto method : {RenderMethod::surface, RenderMethod::splat}) {
        const std::string name = method == RenderMethod::surface ? "surface" : "splat";
        CAPTURE(name);
        const Scene s = block_scene(method);
        {  // at rest: every speed 0, the range 0 to 0, the whole face the colour map's start
            Simulation sim(s, o);
            ImageStyle style;
            style.surface = SurfaceColour::by_speed;
            const Image im = sim.image(face_on(), style);
            CHECK(im.range[0] == 0.0);
            CHECK(im.range[1] == 0.0);
            std::size_t off = 0;
            const auto face = face_pixels(face_on(), 0.0);
            for (const auto& f : face) off += hue_t(&im.rgb[3 * f.index]) > 0.05;
            MESSAGE(off << " of " << face.size() << " face pixels away from the colour map's start");
            CHECK(off <= face.size() / 100);
        }
        // Moving, ranges automatic: the devices' bounds against the host's over the same particles.
        const Particles p = moving(s, o, 0.7);
        Simulation sim(s, p, o);
        const Particles back = sim.particles();
        double top = 0, p_lo = INFINITY, p_hi = -INFINITY;
        for (std::size_t i = 0; i < back.size(); ++i) {
            if (back.type[i] != ParticleType::fluid) continue;
            const auto& v = back.velocity[i];
            top = std::max(top, std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]));
            p_lo = std::min(p_lo, double(back.pressure[i]));
            p_hi = std::max(p_hi, double(back.pressure[i]));
        }
        ImageStyle speed;
        speed.surface = SurfaceColour::by_speed;
        const Image by_speed = sim.image(face_on(), speed);
        CHECK(by_speed.range[0] == 0.0);
        CHECK(by_speed.range[1] == doctest::Approx(top).epsilon(1e-5));
        CHECK(top > 0.6);  // the last particle's x over L, times 0.7
        ImageStyle pressure;
        pressure.surface = SurfaceColour::by_pressure;
        const Image by_pressure = sim.image(face_on(), pressure);
        const double slack = 1e-4 * std::max(std::abs(p_lo), std::abs(p_hi)) + 1e-3;
        CHECK(std::abs(by_pressure.range[0] - p_lo) <= slack);
        CHECK(std::abs(by_pressure.range[1] - p_hi) <= slack);
        CHECK(p_hi > p_lo);  // hydrostatic: deeper is higher
        // One end fixed: the other found.
        ImageStyle half = pressure;
        half.range_max = 2 * p_hi;
        const Image h = sim.image(face_on(), half);
        CHECK(std::abs(h.range[0] - p_lo) <= slack);
        CHECK(h.range[1] == 2 * p_hi);
    }
}
}
