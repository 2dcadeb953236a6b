// The particles brought to the host: all of them (which become the last good state), thinned on
// the devices by a stride and a box, or one part per device; and the last good state itself,
// which a set-up on the devices builds from the scene's plan only when it is first asked for.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/simulation.hpp"
#include "multi/slab_driver.hpp"
#include "scene/lattice_plan.hpp"
#include "simulation/run_state.hpp"

#include <optional>
#include <vector>

namespace clsph::simulation {

class Downloads {
public:
    // `start`: the particles the run was set up from (empty with a plan: the host never held them).
    Downloads(multi::SlabDriver& driver, RunState& state, Particles start, std::optional<scene::LatticePlan> plan)
        : driver_(driver), state_(state), last_good_(std::move(start)), plan_(std::move(plan)) {}
    Particles all();
    std::vector<Particles> by_device(const ParticleSelection& which);
    Particles selected(const ParticleSelection& which);
    const Particles& last_good();

private:
    void keep(Particles p);  // the last good state now
    multi::SlabDriver& driver_;
    RunState& state_;
    Particles last_good_;
    std::optional<scene::LatticePlan> plan_;
};

}  // namespace clsph::simulation
