#include "scene/wave_maker.hpp"

#include "clsph/error.hpp"

#include <cmath>
#include <sstream>

namespace clsph::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string num(double x) {
    std::ostringstream o;
    o.precision(9);
    o << x;
    return o.str();
}

[[noreturn]] void fail(const std::string& key, const std::string& message) { throw SceneError(key + ": " + message); }

double norm(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

}  // namespace

double wave_number_depth(double period, double depth, double g) {
    const double w = 2.0 * kPi / period;
    const double y = w * w * depth / g;  // k0 d, the deep-water value
    double x = y / std::sqrt(std::tanh(y));  // Eckart (1952), within 5 %
    for (int i = 0; i < 100; ++i) {
        const double t = std::tanh(x);
        const double f = x * t - y, df = t + x * (1.0 - t * t);
        const double next = x - f / df;
        const bool done = std::abs(next - x) <= 1e-15 * x;
        x = next > 0 ? next : 0.5 * x;
        if (done) break;
    }
    return x;
}

// With e = exp(-2 kd) every term below is scaled by 2 exp(-2 kd): no overflow for large kd.
double piston_height_ratio(double kd) {
    const double a = -std::expm1(-2.0 * kd);  // 1 - e
    const double e = 1.0 - a;
    return 2.0 * a * a / (a * (2.0 - a) + 4.0 * kd * e);
}

double flap_height_ratio(double kd, double lambda) {
    const double a = -std::expm1(-2.0 * kd);
    const double e = 1.0 - a;
    // 4 sinh kd (cosh kd - cosh(lambda kd)) scaled: 4 (1 - e) ((1 + e) / 2 - cosh(lambda kd) exp(-kd))
    const double c = 0.5 * (std::exp((lambda - 1.0) * kd) + std::exp(-(lambda + 1.0) * kd));
    const double second = 4.0 * a * (0.5 * (1.0 + e) - c) / (kd * (1.0 - lambda));
    return (2.0 * a * a - second) / (a * (2.0 - a) + 4.0 * kd * e);
}

MotionSegment wave_maker_segment(WaveMaker& w, const Vec3& gravity, const std::string& key) {
    const bool flap = w.kind == WaveMaker::Kind::flap;
    auto finite = [&](double v, const char* name) {
        if (!std::isfinite(v)) fail(key + "." + name, "must be a finite number, got " + num(v));
    };
    finite(w.height, "height");
    finite(w.period, "period");
    finite(w.depth, "depth");
    finite(w.ramp, "ramp");
    finite(w.start, "start");
    finite(w.end, "end");
    for (int k = 0; k < 3; ++k) finite(w.direction[k], "direction"), finite(w.hinge[k], "hinge");
    finite(w.hinge_height, "hinge_height");
    if (w.depth <= 0) fail(key + ".depth", "must be a water depth > 0 m, got " + num(w.depth));
    if (w.height <= 0) fail(key + ".height", "must be a wave height > 0 m, got " + num(w.height));
    if (w.period <= 0) fail(key + ".period", "must be a wave period > 0 s, got " + num(w.period));
    if (w.ramp < 0) fail(key + ".ramp", "must be a ramp-up time >= 0 s, got " + num(w.ramp));
    if (!(w.end > w.start)) fail(key + ".end", "must be after start (" + num(w.end) + " <= " + num(w.start) + ")");
    const double g = norm(gravity);
    if (!(g > 0)) fail(key, "a wave maker needs gravity (physics.gravity is zero)");
    const Vec3 up{-gravity[0] / g, -gravity[1] / g, -gravity[2] / g};
    const double dl = norm(w.direction);
    if (!(dl > 0)) fail(key + ".direction", "must not be the zero vector");
    const Vec3 dir{w.direction[0] / dl, w.direction[1] / dl, w.direction[2] / dl};
    if (std::abs(dir[0] * up[0] + dir[1] * up[1] + dir[2] * up[2]) > 1e-9)
        fail(key + ".direction", "must be horizontal (perpendicular to physics.gravity)");
    if (flap && !(w.hinge_height >= 0 && w.hinge_height < w.depth))
        fail(key + ".hinge_height", "must be in [0, depth) m (the hinge's height above the bed, below the still-water level), got " +
                                        num(w.hinge_height));

    const double kd = wave_number_depth(w.period, w.depth, g);
    w.k = kd / w.depth;
    w.wavelength = 2.0 * kPi / w.k;
    const double limit = 0.142 * std::tanh(kd);
    if (w.height / w.wavelength > limit)
        fail(key + ".height", "waves of height " + num(w.height) + " m and length " + num(w.wavelength) + " m (H/L = " +
                                  num(w.height / w.wavelength) + ") are steeper than the breaking limit H/L = 0.142 tanh(kd) = " +
                                  num(limit) + " (kd = " + num(kd) + "); lower the height or lengthen the period");
    const double lambda = flap ? w.hinge_height / w.depth : 0.0;
    const double ratio = flap ? flap_height_ratio(kd, lambda) : piston_height_ratio(kd);
    w.stroke = w.height / ratio;

    MotionSegment s;
    s.start = w.start;
    s.end = w.end;
    s.period = w.period;
    s.phase = 0;
    s.ramp = w.ramp;
    if (!flap) {
        s.type = MotionSegment::Type::ramped_sine;
        for (int k = 0; k < 3; ++k) s.amplitude[k] = 0.5 * w.stroke * dir[k];
    } else {
        s.type = MotionSegment::Type::ramped_sine_rotation;
        s.axis = {up[1] * dir[2] - up[2] * dir[1], up[2] * dir[0] - up[0] * dir[2], up[0] * dir[1] - up[1] * dir[0]};
        s.axis_point = w.hinge;
        s.angle = std::atan(0.5 * w.stroke / (w.depth - w.hinge_height));
    }
    return s;
}

}  // namespace clsph::scene
