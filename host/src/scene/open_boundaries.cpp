#include "scene/open_boundaries.hpp"

#include "clsph/error.hpp"
#include "shared.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace clsph::scene {
namespace {

// Lattice points along an extent: one per dp, at least one (the checks ask for an extent >= dp).
std::int64_t points(double extent, double dp) { return static_cast<std::int64_t>(std::floor(extent / dp + 1e-9)); }

int flow_axis(const Vec3& u) {
    int axis = -1, nonzero = 0;
    for (int k = 0; k < 3; ++k)
        if (u[k] != 0.0) axis = k, ++nonzero;
    return nonzero == 1 ? axis : -1;
}

// The first and last lattice index (multiples of dp, faces included) of [lo, hi].
std::int64_t first_index(double lo, double dp) { return static_cast<std::int64_t>(std::ceil(lo / dp - 1e-9)); }
std::int64_t last_index(double hi, double dp) { return static_cast<std::int64_t>(std::floor(hi / dp + 1e-9)); }

// The profile's factor at a coordinate: linear between its points, the end factors beyond them.
double profile_factor(const InletProfile& p, double c) {
    const auto& q = p.points;
    if (c <= q.front()[0]) return q.front()[1];
    if (c >= q.back()[0]) return q.back()[1];
    std::size_t k = 0;
    while (k + 2 < q.size() && q[k + 1][0] <= c) ++k;
    const double f = (c - q[k][0]) / (q[k + 1][0] - q[k][0]);
    return q[k][1] + f * (q[k + 1][1] - q[k][1]);
}

}  // namespace

bool has_outlet_zones(const Scene& s) {
    return std::any_of(s.outlets.begin(), s.outlets.end(), [](const Outlet& o) { return o.zone; });
}

InletSpeed::InletSpeed(const Inlet& in) {
    const int axis = flow_axis(in.velocity);
    constant_ = axis < 0 ? 0.0 : std::fabs(in.velocity[static_cast<std::size_t>(axis)]);
    varies_ = !in.speed.empty();
    if (varies_) series_ = IntegratedSeries(in.speed);
}

double InletSpeed::at(double t) const { return varies_ ? series_.value(t) : constant_; }
double InletSpeed::travelled(double t) const { return varies_ ? series_.integral(t) : constant_ * t; }
double InletSpeed::mean(double t, double dt) const {
    if (!varies_) return constant_;
    return dt > 0 ? (series_.integral(t + dt) - series_.integral(t)) / dt : series_.value(t);
}
double InletSpeed::max() const { return varies_ ? series_.max() : constant_; }

InletColumns inlet_columns(const Inlet& in, double dp) {
    InletColumns c;
    if (in.profile.axis < 0 || in.profile.points.empty()) {
        c.factor = {1.0};
        return c;
    }
    c.axis = in.profile.axis;
    const auto k = static_cast<std::size_t>(c.axis);
    const std::int64_t lo = first_index(in.min[k], dp), hi = last_index(in.max[k], dp);
    c.first = static_cast<double>(lo) * dp;
    for (std::int64_t j = lo; j <= hi; ++j) c.factor.push_back(profile_factor(in.profile, static_cast<double>(j) * dp));
    return c;
}

std::size_t inlet_streams(const Scene& scene) {
    std::size_t n = 0;
    for (const Inlet& in : scene.inlets) n += inlet_columns(in, scene.physics.dp).factor.size();
    return n;
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
        const auto ax = static_cast<std::size_t>(o.axis);
        o.speed = InletSpeed(in);
        o.sign = in.velocity[ax] > 0 ? 1.0 : -1.0;
        o.upstream = o.sign > 0 ? in.min[ax] : in.max[ax];
        o.layers = points(in.max[ax] - in.min[ax], dp_);
        o.direction = {0, 0, 0};
        o.direction[ax] = o.sign;
        o.surface = in.surface.value_or(in.max[2]);
        const InletColumns columns = inlet_columns(in, dp_);
        o.factor = columns.factor;
        o.profiled = columns.axis >= 0;
        // The cross-section on the scene's lattice (multiples of dp, faces included), as fluid blocks are.
        const int a = (o.axis + 1) % 3, b = (o.axis + 2) % 3;
        for (std::int64_t j = first_index(in.min[a], dp_); j <= last_index(in.max[a], dp_); ++j)
            for (std::int64_t k = first_index(in.min[b], dp_); k <= last_index(in.max[b], dp_); ++k) {
                std::array<double, 3> x{};
                x[static_cast<std::size_t>(a)] = static_cast<double>(j) * dp_;
                x[static_cast<std::size_t>(b)] = static_cast<double>(k) * dp_;
                o.section.push_back(x);
                const std::int64_t along = columns.axis == a ? j : k;  // the lattice index along the profile's axis
                o.stream.push_back(o.profiled ? static_cast<std::size_t>(along - first_index(in.min[static_cast<std::size_t>(columns.axis)], dp_)) : 0);
            }
        o.first_stream = state_.last_layer.size();
        state_.last_layer.insert(state_.last_layer.end(), o.factor.size(), -o.layers);
        inlets_.push_back(o);
    }
}

Particles InletFeed::due(double t) {
    Particles out;
    std::vector<double> moved;
    std::vector<std::int64_t> last;
    for (const One& o : inlets_) {
        // Each stream's distance along the velocity since t = 0 and its last layer due.
        const double travelled = o.speed.travelled(t);
        const double u = o.speed.at(t);
        moved.assign(o.factor.size(), travelled);
        if (o.profiled)
            for (std::size_t s = 0; s < moved.size(); ++s) moved[s] = o.factor[s] * travelled;
        last.resize(moved.size());
        std::int64_t lo = 0, hi = 0;
        bool any = false;
        for (std::size_t s = 0; s < moved.size(); ++s) {
            last[s] = static_cast<std::int64_t>(std::floor(moved[s] / dp_));
            const std::int64_t made = state_.last_layer[o.first_stream + s];
            if (last[s] <= made) continue;
            lo = any ? std::min(lo, made + 1) : made + 1;
            hi = any ? std::max(hi, last[s]) : last[s];
            any = true;
        }
        for (std::int64_t m = lo; any && m <= hi; ++m)
            for (std::size_t q = 0; q < o.section.size(); ++q) {
                const std::size_t s = o.stream[q];
                if (m <= state_.last_layer[o.first_stream + s] || m > last[s]) continue;
                std::array<double, 3> x = o.section[q];
                x[static_cast<std::size_t>(o.axis)] = o.upstream + o.sign * (moved[s] - static_cast<double>(m) * dp_);
                const double p = std::max(0.0, rho0_ * g_ * (o.surface - x[2]));
                const double rho = rho0_ * std::pow(1.0 + p / b_, 1.0 / 7.0);
                if (state_.next_id > CLSPH_ID_MASK)
                    throw Error("inlets: the particle ids ran out (2^31 - 1 particles made since the start)");
                const double v = o.profiled ? u * o.factor[s] : u;
                out.push_back(static_cast<std::uint32_t>(state_.next_id++), ParticleType::fluid, x,
                              {static_cast<float>(o.direction[0] * v), static_cast<float>(o.direction[1] * v),
                               static_cast<float>(o.direction[2] * v)},
                              static_cast<float>(rho), static_cast<float>(p));
            }
        for (std::size_t s = 0; s < moved.size(); ++s) {
            auto& made = state_.last_layer[o.first_stream + s];
            made = std::max(made, last[s]);
        }
    }
    return out;
}

std::vector<double> InletFeed::speeds(double t) const {
    std::vector<double> u;
    for (const One& o : inlets_) u.push_back(o.speed.at(t));
    return u;
}

std::vector<double> InletFeed::mean_speeds(double t, double dt) const {
    std::vector<double> u;
    for (const One& o : inlets_) u.push_back(o.speed.mean(t, dt));
    return u;
}

bool InletFeed::speeds_vary() const {
    return std::any_of(inlets_.begin(), inlets_.end(), [](const One& o) { return o.speed.varies(); });
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
    for (const One& o : inlets_) r += o.speed.max() * *std::max_element(o.factor.begin(), o.factor.end()) / dp_;
    return r;
}

void InletFeed::restore(const InletState& s) {
    if (s.last_layer.size() != state_.last_layer.size())
        throw Error("inlets: the saved state has " + std::to_string(s.last_layer.size()) + " streams, the scene's inlets " +
                    std::to_string(state_.last_layer.size()));
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
