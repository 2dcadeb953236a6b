#include "scene/open_boundaries.hpp"

#include "clsph/error.hpp"
#include "shared.h"

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

// Lattice points along an extent: one per dp, at least one (the checks ask for an extent >= dp).
std::int64_t points(double extent, double dp) { return static_cast<std::int64_t>(std::floor(extent / dp + 1e-9)); }

int flow_axis(const Vec3& u) {
    int axis = -1, nonzero = 0;
    for (int k = 0; k < 3; ++k)
        if (u[k] != 0.0) axis = k, ++nonzero;
    return nonzero == 1 ? axis : -1;
}

}  // namespace

void check_open_boundaries(const Scene& s) {
    const double dp = s.physics.dp;
    for (std::size_t i = 0; i < s.inlets.size(); ++i) {
        const Inlet& in = s.inlets[i];
        const std::string key = "inlets[" + std::to_string(i) + "]";
        for (const auto* v : {&in.min, &in.max, &in.velocity})
            for (double x : *v)
                require(std::isfinite(x), key, "expected finite numbers, got min " + text(in.min) + ", max " + text(in.max) +
                                                   ", velocity " + text(in.velocity));
        const int axis = flow_axis(in.velocity);
        require(axis >= 0, key + ".velocity",
                "must be along one axis (one non-zero component: [u, 0, 0], [0, v, 0] or [0, 0, w]), got " + text(in.velocity));
        for (int k = 0; k < 3; ++k) {
            require(in.max[k] - in.min[k] >= dp * (1 - 1e-9), key + ".max",
                    "the box must be at least dp = " + std::to_string(dp) + " m wide along each axis (min " + text(in.min) +
                        ", max " + text(in.max) + ")");
            require(in.min[k] >= s.domain.min[k] - 1e-9 && in.max[k] <= s.domain.max[k] + 1e-9, key + ".max",
                    "the box must lie inside the domain");
        }
        require(!s.domain.periodic[axis], key + ".velocity",
                std::string("the domain is periodic along ") + "xyz"[axis] + ", the inlet's axis: an inlet needs an open face");
        if (in.surface) require(std::isfinite(*in.surface), key + ".surface", "must be a finite number (m)");
        // Each step moves the buffer less than a column (CFL), and the box must hold one layer.
        require(s.physics.integrator == Integrator::leapfrog, key,
                "inlets need physics.integrator \"leapfrog\" (the Symplectic step has two exchanges)");
        require(!s.has_floating(), key, "inlets do not run with floating bodies yet");
    }
    for (std::size_t i = 0; i < s.outlets.size(); ++i) {
        const Outlet& o = s.outlets[i];
        require(!s.domain.periodic[static_cast<std::size_t>(o.axis)], "outlets[" + std::to_string(i) + "].face",
                std::string("the domain is periodic along ") + "xyz"[o.axis] + ": an outlet needs an open face");
    }
}

InletFeed::InletFeed(const Scene& scene, std::uint64_t first_id) {
    const auto& ph = scene.physics;
    dp_ = ph.dp;
    rho0_ = ph.rho0;
    const double c0 = scene.inlets.empty() ? 0.0 : scene.sound_speed();
    b_ = c0 * c0 * rho0_ / ph.gamma;
    g_ = -ph.gravity[2];
    state_.next_id = first_id;
    for (const Inlet& in : scene.inlets) {
        One o;
        o.axis = flow_axis(in.velocity);
        o.speed = std::fabs(in.velocity[static_cast<std::size_t>(o.axis)]);
        o.sign = in.velocity[static_cast<std::size_t>(o.axis)] > 0 ? 1.0 : -1.0;
        o.upstream = o.sign > 0 ? in.min[static_cast<std::size_t>(o.axis)] : in.max[static_cast<std::size_t>(o.axis)];
        o.layers = points(in.max[static_cast<std::size_t>(o.axis)] - in.min[static_cast<std::size_t>(o.axis)], dp_);
        o.velocity = in.velocity;
        o.surface = in.surface.value_or(in.max[2]);
        // The cross-section on the scene's lattice (multiples of dp, faces included), as fluid blocks are.
        const int a = (o.axis + 1) % 3, b = (o.axis + 2) % 3;
        auto first = [&](int k) { return static_cast<std::int64_t>(std::ceil(in.min[k] / dp_ - 1e-9)); };
        auto last = [&](int k) { return static_cast<std::int64_t>(std::floor(in.max[k] / dp_ + 1e-9)); };
        for (std::int64_t j = first(a); j <= last(a); ++j)
            for (std::int64_t k = first(b); k <= last(b); ++k) {
                std::array<double, 3> x{};
                x[static_cast<std::size_t>(a)] = static_cast<double>(j) * dp_;
                x[static_cast<std::size_t>(b)] = static_cast<double>(k) * dp_;
                o.section.push_back(x);
            }
        inlets_.push_back(o);
        state_.last_layer.push_back(-o.layers);
    }
}

Particles InletFeed::due(double t) {
    Particles out;
    for (std::size_t i = 0; i < inlets_.size(); ++i) {
        const One& o = inlets_[i];
        const double moved = o.speed * t;  // along the velocity since t = 0
        const auto last = static_cast<std::int64_t>(std::floor(moved / dp_));
        for (std::int64_t m = state_.last_layer[i] + 1; m <= last; ++m) {
            const double along = o.upstream + o.sign * (moved - static_cast<double>(m) * dp_);
            for (const auto& q : o.section) {
                std::array<double, 3> x = q;
                x[static_cast<std::size_t>(o.axis)] = along;
                const double p = std::max(0.0, rho0_ * g_ * (o.surface - x[2]));
                const double rho = rho0_ * std::pow(1.0 + p / b_, 1.0 / 7.0);
                if (state_.next_id > CLSPH_ID_MASK)
                    throw Error("inlets: the particle ids ran out (2^31 - 1 particles made since the start)");
                out.push_back(static_cast<std::uint32_t>(state_.next_id++), ParticleType::fluid, x,
                              {static_cast<float>(o.velocity[0]), static_cast<float>(o.velocity[1]),
                               static_cast<float>(o.velocity[2])},
                              static_cast<float>(rho), static_cast<float>(p));
            }
            state_.last_layer[i] = m;
        }
    }
    return out;
}

std::uint64_t InletFeed::buffer_particles() const {
    std::uint64_t n = 0;
    for (const One& o : inlets_) n += static_cast<std::uint64_t>(o.layers) * o.section.size();
    return n;
}

std::uint64_t InletFeed::layer_particles() const {
    std::uint64_t n = 0;
    for (const One& o : inlets_) n += o.section.size();
    return n;
}

double InletFeed::layers_per_second() const {
    double r = 0;
    for (const One& o : inlets_) r += o.speed / dp_;
    return r;
}

void InletFeed::restore(const InletState& s) {
    if (s.last_layer.size() != inlets_.size())
        throw Error("inlets: the saved state has " + std::to_string(s.last_layer.size()) + " inlets, the scene " +
                    std::to_string(inlets_.size()));
    state_ = s;
}

std::uint64_t planned_with_inlets(const Scene& scene, std::uint64_t scene_particles) {
    if (scene.inlets.empty()) return scene_particles;
    std::uint64_t n = scene_particles;
    for (std::size_t i = 0; i < scene.inlets.size(); ++i) {
        Scene one = scene;
        one.inlets = {scene.inlets[i]};
        const InletFeed f(one, 0);
        const int axis = flow_axis(scene.inlets[i].velocity);
        const double length = scene.domain.max[static_cast<std::size_t>(axis)] - scene.domain.min[static_cast<std::size_t>(axis)];
        n += f.buffer_particles() + f.layer_particles() * static_cast<std::uint64_t>(points(length, scene.physics.dp) + 1);
    }
    return n;
}

}  // namespace clsph::scene
