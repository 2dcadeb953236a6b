// The checks of a scene's inlets and outlets (scene/open_boundaries.hpp): every error names its key.
#include "clsph/error.hpp"
#include "scene/open_boundaries.hpp"
#include "scene/time_series.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace clsph::scene {
namespace {

void require(bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw SceneError(key + ": " + what);
}

std::string text(const Vec3& v) {
    std::ostringstream o;
    o << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
    return o.str();
}

int flow_axis(const Vec3& u) {
    int axis = -1, nonzero = 0;
    for (int k = 0; k < 3; ++k)
        if (u[k] != 0.0) axis = k, ++nonzero;
    return nonzero == 1 ? axis : -1;
}

// A box at least dp wide along each axis, inside the domain ("key.max" names the error).
void check_box(const Scene& s, const Vec3& min, const Vec3& max, const std::string& key) {
    const double dp = s.physics.dp;
    for (const auto* v : {&min, &max})
        for (double x : *v) require(std::isfinite(x), key, "expected finite numbers, got min " + text(min) + ", max " + text(max));
    for (int k = 0; k < 3; ++k) {
        require(max[k] - min[k] >= dp * (1 - 1e-9), key + ".max",
                "the box must be at least dp = " + std::to_string(dp) + " m wide along each axis (min " + text(min) + ", max " +
                    text(max) + ")");
        require(min[k] >= s.domain.min[k] - 1e-9 && max[k] <= s.domain.max[k] + 1e-9, key + ".max", "the box must lie inside the domain");
    }
}

// What an open boundary with a zone needs of the rest of the scene.
void check_step(const Scene& s, const std::string& key, const char* what) {
    require(s.physics.integrator == Integrator::leapfrog, key,
            std::string(what) + " need physics.integrator \"leapfrog\" (the Symplectic step has two exchanges)");
    require(!s.has_floating(), key, std::string(what) + " do not run with floating bodies yet");
}

void check_inlet(const Scene& s, const Inlet& in, const std::string& key) {
    for (double x : in.velocity) require(std::isfinite(x), key, "expected finite numbers, got velocity " + text(in.velocity));
    check_box(s, in.min, in.max, key);
    const int axis = flow_axis(in.velocity);
    require(axis >= 0, key + ".velocity",
            "must be along one axis (one non-zero component: [u, 0, 0], [0, v, 0] or [0, 0, w]), got " + text(in.velocity));
    require(!s.domain.periodic[static_cast<std::size_t>(axis)], key + ".velocity",
            std::string("the domain is periodic along ") + "xyz"[axis] + ", the inlet's axis: an inlet needs an open face");
    if (in.surface) require(std::isfinite(*in.surface), key + ".surface", "must be a finite number (m)");
    if (!in.speed.empty()) {
        require(std::fabs(in.velocity[static_cast<std::size_t>(axis)]) == 1.0, key + ".velocity",
                "with a speed in time (speed_csv, speed_series) give the direction only, one component 1 or -1 "
                "([1, 0, 0], [0, -1, 0], ...): the rows give the speed; got " + text(in.velocity));
        check_series(in.speed, key + ".speed_series", SeriesColumn{"speed", "m/s", 0.0});
    }
    const InletProfile& p = in.profile;
    if (p.axis >= 0 || !p.points.empty()) {
        require(p.axis >= 0 && p.axis < 3, key + ".profile.axis", "required: \"x\", \"y\" or \"z\", an axis across the flow");
        require(p.axis != axis, key + ".profile.axis",
                std::string("must lie across the flow; the inlet flows along ") + "xyz"[axis]);
        require(p.points.size() >= 2, key + ".profile.points", "expected at least 2 points [coordinate, factor]");
        for (std::size_t i = 0; i < p.points.size(); ++i) {
            const std::string at = key + ".profile.points[" + std::to_string(i) + "]";
            require(std::isfinite(p.points[i][0]) && std::isfinite(p.points[i][1]), at, "expected finite numbers");
            require(p.points[i][1] >= 0, at, "the factor must be >= 0 (the buffer never flows backwards), got " + std::to_string(p.points[i][1]));
            require(i == 0 || p.points[i][0] > p.points[i - 1][0], at, "the coordinates must increase");
        }
    }
    check_step(s, key, "inlets");
}

void check_outlet(const Scene& s, const Outlet& o, const std::string& key) {
    require(o.axis >= 0 && o.axis < 3, key + ".face", "required: one of \"x-\", \"x+\", \"y-\", \"y+\", \"z-\", \"z+\"");
    const int held = (o.pressure ? 1 : 0) + (o.level ? 1 : 0) + (o.level_series.empty() ? 0 : 1);
    if (!o.zone) {
        require(!s.domain.periodic[static_cast<std::size_t>(o.axis)], key + ".face",
                std::string("the domain is periodic along ") + "xyz"[o.axis] + ": an outlet needs an open face");
        require(held == 0, key + (o.pressure ? ".pressure" : o.level ? ".level" : ".level_series"),
                "needs a zone (min and max): a face of the domain holds no pressure or level");
        return;
    }
    check_box(s, o.min, o.max, key);
    require(held <= 1, key, "give one of pressure, level and level_series (level_csv), not several");
    if (o.pressure) require(std::isfinite(*o.pressure) && *o.pressure >= 0, key + ".pressure", "must be a finite number >= 0 (Pa)");
    if (o.level) require(std::isfinite(*o.level), key + ".level", "must be a finite number (m)");
    if (!o.level_series.empty()) check_series(o.level_series, key + ".level_series", SeriesColumn{"level", "m"});
    check_step(s, key, "outlet zones");
}

}  // namespace

void check_open_boundaries(const Scene& s) {
    for (std::size_t i = 0; i < s.inlets.size(); ++i) check_inlet(s, s.inlets[i], "inlets[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < s.outlets.size(); ++i) check_outlet(s, s.outlets[i], "outlets[" + std::to_string(i) + "]");
}

}  // namespace clsph::scene
