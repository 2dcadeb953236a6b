// How a Simulation runs (clsph/simulation.hpp): its devices, interaction form, balance, waits,
// the step ahead, set-up and ranks. Apart from the facade so that the memory plan and host
// programs that only plan can name it.
#pragma once
#include "clsph/interaction.hpp"
#include "clsph/ranks.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace clsph {
namespace testing {
struct Seams;  // internal: tests and benchmarks only (not an installed header)
}

// How the host waits for the devices' work (several devices): sleeping on event callbacks where
// the driver delivers them on time and polling the events' status elsewhere (the default),
// always polling, or blocking in clWaitForEvents (on time everywhere, but it spins a core on NVIDIA).
enum class WaitMode { callbacks, poll, block };

// How the slab cuts between several devices are chosen (docs/balance.md): every step from the
// devices' measured times (dynamic), once by equal work before the first step (fixed; `--balance
// static`), or equal column widths that never move (off).
enum class BalanceMode { dynamic, fixed, off };
// "dynamic", "static", "off" (the --balance names) to the mode; throws clsph::Error otherwise.
BalanceMode balance_mode_from_name(const std::string& name);

struct Options {
    std::string devices;       // selection spec (clsph/devices.hpp); empty: $CLSPH_DEVICES or default
    bool profile = false;      // per-kernel times (profile())
    bool trace = false;        // with profile: every command's device timestamps too (take_trace())
    // The interaction form (clsph/interaction.hpp); automatic: the scene's run.interaction, which
    // defaults to a choice per device type.
    Interaction interaction = Interaction::automatic;
    // The order within cells (clsph/interaction.hpp); automatic: the scene's run.cell_order, which
    // defaults to morton where every device runs lanes.
    CellOrder cell_order = CellOrder::automatic;
    double capacity_headroom = 0.25;  // spare particle capacity per device (several devices)
    BalanceMode balance = BalanceMode::dynamic;
    std::string balance_log;          // several devices: per-step balancer CSV, empty: none
    WaitMode wait = WaitMode::callbacks;
    // synchronous (the library's default): the host waits for every step, so an exception thrown
    // by the step callback leaves the state at that step. Off: the step ahead (one device with
    // cl_khr_fp64; docs/multi_device.md): dt chosen on the device, no count read back per step,
    // each step's statistics read up to steps_ahead steps later — bitwise the same states, but an
    // exception from the callback leaves the state (and info()) at the last step in flight. The
    // clsph tool runs steps ahead unless --synchronous.
    bool synchronous = true;
    std::size_t steps_ahead = 8;    // steps in flight at most (the ring of results)
    double cell_headroom = 0.25;    // spare capacity of the cell tables, whose bound the step ahead launches over
    // A CFL step below this fraction of the acoustic step at rest (cfl h / c0) stops the run with a
    // SimulationError, as a blow-up does (1e-3: accelerations of ~1e6 c0^2/h). Not with fixed_dt.
    double dt_collapse = 1e-3;
    // --steps: the step ahead enqueues no step past this one (0: no limit), so a run stopped there
    // by the step callback has taken exactly that many steps (run_until returns there, short of t).
    std::uint64_t step_limit = 0;
    // Scenes of walls, boxes and fluid blocks (no meshes, at most 64 blocks): each device generates
    // its own slab's particles (set-up on the device); the host never holds them all, so
    // last_good() is empty until particles() is first called. Off: built by
    // Scene::build_particles() on the host and uploaded (the same particles, slower).
    bool setup_on_device = true;
    // A line per stage of the set-up (planning, timing the devices, generating, sorting); empty: quiet.
    std::function<void(const std::string&)> on_setup;
    // Several processes (clsph/ranks.hpp, `mpirun`): this rank's part of one run. `devices` then
    // names the node's devices, dealt to the node's ranks, or each rank's (the per-rank form,
    // docs/mpi.md). particles() and the step's figures: this rank's particles; the reductions
    // (time step, energies, counts, probes) over every rank. Null: one process.
    std::shared_ptr<Ranks> ranks;
    // Tests and benchmarks only: deliberate misbehaviour (host/testing/clsph/testing.hpp, not
    // installed: a host program cannot set it); null: none.
    std::shared_ptr<const testing::Seams> seams;
};

}  // namespace clsph
