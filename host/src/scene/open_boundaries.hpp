// Open boundaries (docs/scenes.md, inlets and outlets): the checks of a scene's inlets and outlets,
// and the particles each inlet creates. Pure C++: no device here.
//
// Ids without communication: an inlet's layers are numbered m = 1 - L, ..., 0, 1, 2, ... (L the
// layers the box holds). With X(t) the distance the inlet's speed u(t) carries it from t = 0 (u t
// for a constant speed; the exact integral of a series' linear pieces), layer m exists at time t
// once X(t) >= m dp, and lies at upstream + (X(t) - m dp) along the velocity (so it enters the box
// at its upstream face), its particles on the scene's lattice across the box (multiples of dp, as
// fluid blocks). With a profile each lattice point along the profile's axis is a stream of its own,
// at factor X(t). The host of every device and rank asks due(t) at the same times with the same
// state (each stream's last layer, the next id), so every one of them makes the same particles with
// the same ids, in the same order (inlet, layer, lattice point); each device keeps those in its
// columns (multi/exchange.cpp).
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"
#include "scene/time_series.hpp"

#include <cstdint>
#include <vector>

namespace clsph::scene {

// Throws SceneError naming the key (inlets[i].velocity, outlets[i].face, ...).
void check_open_boundaries(const Scene& scene);

// Outlets with a zone (a box: pressure, level, or only the face past which fluid is removed).
bool has_outlet_zones(const Scene& scene);

// An inlet's speed along its direction: |velocity|, or its series in time.
class InletSpeed {
public:
    InletSpeed() = default;
    explicit InletSpeed(const Inlet& in);
    double at(double t) const;         // m/s
    double travelled(double t) const;  // X(t), m since t = 0
    // What moves the buffer by exactly X(t + dt) - X(t) in a step of dt: that over dt (a constant
    // speed: itself).
    double mean(double t, double dt) const;
    double max() const;
    bool varies() const { return varies_; }

private:
    double constant_ = 0;
    IntegratedSeries series_;
    bool varies_ = false;
};

// The lattice of an inlet's section along its profile's axis: the first coordinate and each
// point's factor (without a profile one stream of factor 1 and axis -1).
struct InletColumns {
    int axis = -1;
    double first = 0;  // m
    std::vector<double> factor;
};
InletColumns inlet_columns(const Inlet& in, double dp);
// The streams of a scene's inlets (a checkpoint's InletState::last_layer has one entry each).
std::size_t inlet_streams(const Scene& scene);

// What a run resumes from (Checkpoint::inlets): the next id and each stream's last layer made.
struct InletState {
    std::uint64_t next_id = 0;
    std::vector<std::int64_t> last_layer;  // per stream (inlets in order); -L: none yet
};

class InletFeed {
public:
    // first_id: the first id not held by the scene's own particles.
    InletFeed(const Scene& scene, std::uint64_t first_id);
    bool empty() const { return inlets_.empty(); }
    // The layers due by time t not made yet (positions at t), their ids from next_id; advances.
    Particles due(double t);
    // Each inlet's speed at t, and what moves its buffer by exactly X(t + dt) - X(t) (InletSpeed).
    std::vector<double> speeds(double t) const;
    std::vector<double> mean_speeds(double t, double dt) const;
    bool speeds_vary() const;  // some inlet's speed follows a series
    // The particles every inlet's box holds (its buffer), for the memory plan.
    std::uint64_t buffer_particles() const;
    // The particles one layer of all inlets holds, and the most layers per second they make (at
    // the largest speed of each inlet's series and of its profile's factors).
    std::uint64_t layer_particles() const;
    double layers_per_second() const;
    const InletState& state() const { return state_; }
    void restore(const InletState& s);

private:
    struct One {
        int axis = 0;
        double sign = 1, upstream = 0;
        InletSpeed speed;
        std::int64_t layers = 0;
        std::vector<std::array<double, 3>> section;  // the lattice points of a layer (axis coordinate 0)
        std::vector<std::size_t> stream;             // per section point: its stream (an index into factor)
        std::vector<double> factor;                  // per stream
        bool profiled = false;
        std::size_t first_stream = 0;                // its streams' place in state_.last_layer
        Vec3 direction{};
        double surface = 0;
    };
    std::vector<One> inlets_;
    InletState state_;
    double dp_ = 0, rho0_ = 0, b_ = 0, g_ = 0;
};

// Particles a run may hold at most with its inlets (the memory plan's capacity): the scene's own,
// the inlets' buffers and as many layers as would fill the domain along each inlet's axis (whatever
// the speed: the count that fills the domain once does not depend on how fast it comes).
std::uint64_t planned_with_inlets(const Scene& scene, std::uint64_t scene_particles);

}  // namespace clsph::scene
