// Open boundaries (docs/scenes.md, inlets and outlets): the checks of a scene's inlets and outlets,
// and the particles each inlet creates. Pure C++: no device here.
//
// Ids without communication: an inlet's layers are numbered m = 1 - L, ..., 0, 1, 2, ... (L the
// layers the box holds); layer m exists at time t once |u| t >= m dp, and lies at
// upstream + (|u| t - m dp) along the velocity (so it enters the box at its upstream face), its
// particles on the scene's lattice across the box (multiples of dp, as fluid blocks). The host of every device and rank asks due(t) at the same times with the same state
// (the layers made so far, the next id), so every one of them makes the same particles with the
// same ids, in the same order; each device keeps those in its columns (multi/exchange.cpp).
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <cstdint>
#include <vector>

namespace clsph::scene {

// Throws SceneError naming the key (inlets[i].velocity, outlets[i].face, ...).
void check_open_boundaries(const Scene& scene);

// What a run resumes from (Checkpoint::inlets): the next id and each inlet's last layer made.
struct InletState {
    std::uint64_t next_id = 0;
    std::vector<std::int64_t> last_layer;  // per inlet; 1 - L - 1 = -L: none yet
};

class InletFeed {
public:
    // first_id: the first id not held by the scene's own particles.
    InletFeed(const Scene& scene, std::uint64_t first_id);
    bool empty() const { return inlets_.empty(); }
    // The layers due by time t not made yet (positions at t), their ids from next_id; advances.
    Particles due(double t);
    // The particles every inlet's box holds (its buffer), for the memory plan.
    std::uint64_t buffer_particles() const;
    // The particles one layer of all inlets holds, and the layers per second they make.
    std::uint64_t layer_particles() const;
    double layers_per_second() const;
    const InletState& state() const { return state_; }
    void restore(const InletState& s);

private:
    struct One {
        int axis = 0;
        double sign = 1, speed = 0, upstream = 0;
        std::int64_t layers = 0;
        std::vector<std::array<double, 3>> section;  // the lattice points of a layer (axis coordinate 0)
        Vec3 velocity{};
        double surface = 0;
    };
    std::vector<One> inlets_;
    InletState state_;
    double dp_ = 0, rho0_ = 0, b_ = 0, g_ = 0;
};

// Particles a run may hold at most with its inlets (the memory plan's capacity): the scene's own,
// the inlets' buffers and as many layers as would fill the domain along each inlet's axis.
std::uint64_t planned_with_inlets(const Scene& scene, std::uint64_t scene_particles);

}  // namespace clsph::scene
