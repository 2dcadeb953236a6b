// One simulation over one or more devices (docs/multi_device.md): the domain is cut into slabs of
// cell columns along the split axis, one per device, and every step is the same list of phases on
// every device count — drift, balance, exchange, tables, forces, kick, reductions (step()). The
// parts: Partition (columns, cuts, needs, the first upload), calibrate() (before the first step),
// Exchange (settle, send through Links, merge, tables), DeviceThreads (one host thread per
// device), ForceTimer (the balancer's input), balance::Balancer (the cuts).
#pragma once
#include "balance/balance_log.hpp"
#include "balance/balancer.hpp"
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "cl/relay.hpp"
#include "clsph/checkpoint.hpp"
#include "clsph/interaction.hpp"
#include "clsph/scene.hpp"
#include "clsph/testing.hpp"
#include "device/grid.hpp"
#include "device/sizing.hpp"
#include "multi/device_threads.hpp"
#include "multi/exchange.hpp"
#include "multi/list_schedule.hpp"
#include "multi/partition.hpp"
#include "multi/phase_timer.hpp"
#include "multi/rigid_bodies.hpp"
#include "multi/slab.hpp"
#include "scene/lattice_plan.hpp"
#include "scene/open_boundaries.hpp"

#include <array>
#include <fstream>
#include <map>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace clsph::multi {

struct DriverOptions {
    Interaction interaction = Interaction::automatic;
    CellOrder cell_order = CellOrder::automatic;  // resolved over every device (also other ranks')
    balance::Mode balance = balance::Mode::dynamic;
    std::string balance_log;  // CSV path, empty: none
    double headroom = 0.25;   // spare particle capacity per device
    double cell_headroom = 0.25;  // spare capacity of the cell tables
    cl_rt::EventSet::Mode wait = cl_rt::EventSet::Mode::callbacks;
    testing::Seams seams;
    // Non-empty (devices + 1 columns): the first cuts (a checkpoint's), instead of the balancer's.
    std::vector<std::size_t> cuts;
    // A line per stage of a long set-up (generating, calibrating); empty: quiet.
    std::function<void(const std::string&)> progress;
    // Several processes (clsph/ranks.hpp): the devices given are this rank's, its slabs follow the
    // slabs of the ranks before it. Null: one process.
    std::shared_ptr<Ranks> ranks;
    // Inlets (scene/open_boundaries.hpp): where a resumed run's feed stands, and the time of the
    // first pass (a checkpoint's; 0 for a new run). Null: a new run's.
    std::optional<scene::InletState> inlet_state;
    double start_time = 0.0;
    // From a checkpoint: its particles and bodies are the state (restore_owned); a new run's
    // floating bodies start at the scene's initial velocities instead.
    bool resumed = false;
};

struct StepOutcome {
    device::KickResult kick;   // over all devices (bad_index: see bad_slab)
    std::size_t bad_slab = 0;
    std::size_t removed = 0;
    std::size_t created = 0;  // by the inlets
};

class SlabDriver {
public:
    SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
               const Particles& particles, const DriverOptions& options);
    // Set-up on the devices: each generates its slab of the plan (device/generate.hpp); the host
    // holds only the boundary particles when mDBC needs their ghost nodes, and calibration samples.
    SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
               const scene::LatticePlan& plan, const DriverOptions& options);

    StepOutcome start();  // the first exchange, forces and a zero kick
    // `time`: the simulated time before the step (where moving solids are put: kernels/motion.cl).
    StepOutcome step(double dt, double time = 0.0);
    Particles download();  // owned particles of every device
    // Slab d's owned particles whose id is divisible by stride, in the box if any (device/thin_download.hpp).
    Particles download_every(std::size_t d, std::uint32_t stride, const std::optional<std::array<double, 6>>& box);

    // The step ahead (docs/multi_device.md): a whole step enqueued with no host wait; each device's
    // record (device::StepRecord) is read into records[d] once `done` is waited for. On one device
    // with a clock; on several with the cell tables kept over steps (run.list_buffer: the steps
    // ahead keep them; a step that must build them halts, kHaltLists, and the host takes it
    // synchronously with step()). Leap-frog only: a Symplectic step has two exchanges; none with
    // floating bodies, whose forces the host sums each step.
    bool can_step_ahead(bool synchronous, std::size_t steps_ahead) const {
        bool clocks = true;
        for (const auto& s : slabs_) clocks = clocks && s.physics && s.physics->has_clock();
        // Copies across contexts complete user events (cl/relay.hpp), which stops pocl's basic device.
        for (const auto& s : slabs_)
            clocks = clocks && (slabs_.size() == 1 || !s.device->quirks().user_events_stop);
        return !across_ranks() && !bodies_ && feed_.empty() && !outlet_zones_ &&
               device::sizing::step_ahead(synchronous, steps_ahead, slabs_.size(), clocks, symplectic_, lists_.on());
    }
    // Before the first step ahead: `slots` steps in flight at most, the probe points sampled in the
    // queue (each on the slab that owns it: probe_owners() says which, in point order).
    void start_ahead(std::size_t slots, const std::vector<std::array<double, 3>>& probe_points);
    const std::vector<std::vector<std::size_t>>& probe_owners() const { return probe_owners_; }
    // With nothing in flight: every device's clock (and the kept tables' bound from 0, and the
    // probes' owners, for the cuts of the last build), then steps ahead again.
    void set_clock(double time, double next_dt, double event);
    // run.list_buffer: whether the step of dt after the last one taken must build the tables.
    bool builds_next(double dt) const { return lists_.on() && lists_.due(dt, last_kick_.max_speed2, last_kick_.max_accel2); }
    // run.list_buffer: whether `steps` more steps of about dt after the last one taken will likely
    // keep the tables (ListSchedule::likely_kept, a margin of kKeptMargin); always true otherwise.
    bool likely_kept(std::size_t steps, double dt) const {
        return !lists_.on() || lists_.likely_kept(steps, dt, last_kick_.max_speed2, last_kick_.max_accel2, kKeptMargin);
    }
    // Each step ahead may move the particles this much more than the last known step did before
    // the host stops enqueueing: a step computed past a build is thrown away (a force pass for
    // nothing), a step held back costs a host round trip.
    static constexpr double kKeptMargin = 1.25;
    void enqueue_step_ahead(std::size_t slot, const std::vector<double*>& records, cl_rt::EventSet& done);
    // With nothing in flight: no device halted (kernels/step_clock.cl), before a synchronous step.
    void clear_halts();
    // A step ahead taken (its record, over every device): the kept tables' bound, the balancer's
    // force times once nothing is in flight.
    void took_step_ahead(double dt, const device::KickResult& kick, bool idle);
    // Steps enqueued that halted (changed nothing): uncounted.
    void dropped_steps_ahead(std::size_t n) { steps_ -= n; }
    // After a step halted on the cell tables' bound: tables grown to `cells`, the step again from
    // its settle (its drift is done; the steps after it changed nothing and are uncounted).
    void redo_step_ahead(std::size_t cells, std::size_t uncounted, std::size_t slot, double* record,
                         cl_rt::EventSet& done);
    // Particles that left the domain wait at the end of the sorted arrays until no step is in flight.
    void drop_left(std::size_t n) { slabs_[0].store->ranges.owned -= n; }
    std::size_t cell_capacity() const { return slabs_[0].cells->cell_capacity(); }
    std::vector<std::array<float, 2>> probe(const std::vector<std::array<double, 3>>& points);

    // A checkpoint's slab arrays (multi/slab_state.cpp): every slab's owned particles appended to
    // c in slab order (across ranks gathered to rank 0, the others' c holding none: collective),
    // and put back over the owned particles the first pass sorted (by id where the split differs
    // from the saved one).
    void save_owned(Checkpoint& c);
    void restore_owned(const Checkpoint& c);
    // Floating bodies (multi/slab_floating.cpp; null: none): their state, integrated on the host.
    RigidBodies* rigid_bodies() { return bodies_.get(); }
    // Inlets: where their feed stands (a checkpoint's part; empty last_layer: no inlet).
    const scene::InletState& inlet_state() const { return feed_.state(); }
    const RigidBodies* rigid_bodies() const { return bodies_.get(); }

    const SphParams& params() const { return params_; }  // the same on every slab
    CellOrder cell_order() const { return cell_order_; }  // the order within cells (never automatic)
    // Every slab of the run; across ranks only this rank's have a device (here(d)).
    std::vector<Slab>& slabs() { return slabs_; }
    bool here(std::size_t d) const { return ranks_.here(d); }
    bool across_ranks() const { return ranks_.ranks != nullptr; }
    Ranks* ranks() const { return ranks_.ranks; }  // across ranks: this run's; null in one process
    // Whether this process writes the run's shared files (a checkpoint): in one process yes, across
    // ranks rank 0 alone.
    bool writes_shared_files() const { return !across_ranks() || ranks_.ranks->rank() == 0; }
    std::vector<std::size_t> cuts() const { return Partition::cuts(slabs_); }
    std::size_t owned() const;
    std::size_t columns() const { return partition_.columns(); }
    // Host wall time spent in each phase of the step since the start (where the time goes).
    const PhaseTotals& phase_seconds() const { return phases_; }
    // run.list_buffer: when the cell tables (and cluster lists) were built (every step without it).
    const ListSchedule& lists() const { return lists_; }

private:
    StepOutcome step_here(double dt, double time);
    // DriverOptions::cell_order, resolved over every device of the run, given to each pipeline.
    void resolve_cell_order();
    CellOrder cell_order_ = CellOrder::arrival;
    void set_up(const std::vector<cl_rt::Device*>& devices, const Scene& scene, const Particles* particles,
                const scene::LatticePlan* plan);
    void for_each_device(const PerDevice& work);
    void apply_seams();
    // The first kick and drift: the host's part (floating bodies, inlet means) now; what each device
    // enqueues is returned, for the exchange to run first on each device's thread (the settle
    // then follows the drift in the queue without a gap).
    PerDevice drift(double dt, double time);
    void rebalance();
    void forces(std::size_t d);
    void kick(std::size_t d, double dt, cl_rt::EventSet& kicked);
    void correct(std::size_t d, double dt, double time);
    StepOutcome reductions(cl_rt::EventSet& kicked);
    // With `drift`: the step's first kick and drift in the cell pass's first launch (fused).
    void tables_forces_kick_ahead(std::size_t slot, double* record, cl_rt::EventSet& done, bool drift);
    // A step ahead with the cell tables kept, on every device (multi/slab_driver_ahead.cpp).
    void kept_step_ahead(std::size_t slot, const std::vector<double*>& records, cl_rt::EventSet& done);
    // Staging of the step sums' copies across contexts: per sender, receiver and slot.
    std::map<std::array<std::size_t, 3>, std::unique_ptr<cl_rt::PinnedHost>> sums_staging_;
    std::vector<std::vector<std::size_t>> probe_owners_;  // per slab: the probe points it samples
    std::size_t slots_ = 0;  // steps in flight at most
    std::vector<std::array<double, 3>> probe_points_;
    // The force pass of device d (forces: on its thread after the exchange; interior_forces: the
    // part the exchange runs while the arrivals travel), each repeated as the slowdown seam says.
    int force_repeats(std::size_t d) const;
    void interior_forces(std::size_t d, std::size_t first, std::size_t last);
    void read_force_times();
    // Floating bodies: the poses after the first half of a step (empty without bodies); the sums of
    // every device and rank; the corrector's pose put on every device; the forces taken and kicked.
    // start_bodies: a new run's bodies given initial velocities put them on their particles.
    void set_up_motion(const Scene& scene);
    void start_bodies();
    std::vector<std::array<double, 18>> drift_bodies(double dt);
    std::vector<std::int64_t> body_sums();
    void correct_bodies(double dt, double time);
    void take_body_forces(double dt);
    std::unique_ptr<RigidBodies> bodies_;
    // mDBC on several devices: each body particle with a ghost node (its body, its offset from the
    // centre and its ghost-node offset, at rest); every step the cuts are kept where each slab
    // holds the fluid around its body particles' ghost nodes, from the bodies' present poses.
    struct BodyGhost { std::size_t body; std::array<double, 3> r0; std::array<float, 3> ghost; };
    std::vector<BodyGhost> body_ghosts_;
    double body_support_ = 0;
    void set_up_body_cuts(const Scene& scene, const Particles& at_rest, const std::vector<std::array<float, 3>>& offsets);
    void keep_cuts_off_bodies(bool move_cuts = true);
    scene::InletFeed feed_;  // inlets: the particles they make (empty: none)
    // The inlets' particles due by `time` (every host alike), or null when none are.
    const Particles* created_by(double time);
    Particles created_;
    // Inlets: each one's speed at the end of the step (after the force pass) and, where a speed
    // follows a series, what moves its buffer by its travel over the step (before the drift).
    std::vector<double> inlet_speeds_, inlet_means_;
    // Outlet zones (scene/open_boundaries.hpp): the time the force pass's level is for.
    bool outlet_zones_ = false;
    double outlet_time_ = 0;

    // run.list_buffer > 0: the tables kept over steps while no particle can have moved half the
    // buffer (ListSchedule), from the last step's reductions (last_kick_).
    ListSchedule lists_;
    device::KickResult last_kick_;
    void set_up_lists(const Scene& scene);

    Partition partition_;
    DriverOptions options_;
    std::vector<Slab> slabs_;
    std::unique_ptr<balance::Balancer> balancer_;
    std::unique_ptr<std::ofstream> log_file_;
    std::unique_ptr<balance::BalanceLog> log_;
    std::unique_ptr<DeviceThreads> threads_;  // several devices: started at the first use
    std::unique_ptr<Exchange> exchange_;
    RankMap ranks_;
    std::shared_ptr<Ranks> own_ranks_;  // across ranks: a communicator of this run's own
    // Across ranks, every slab's figures the balancer reads (gathered after each step).
    struct SlabFigures { double force_seconds = 0; std::size_t owned = 0, global_memory = 0; };
    std::vector<SlabFigures> figures_;
    void gather_figures();
    PhaseTotals phases_;
    SphParams params_{};  // the scene's (device/physics.hpp), also on a rank without slabs
    std::uint64_t steps_ = 0;
    bool symplectic_ = false;
    std::size_t removed_at_upload_ = 0;
    // The steps ahead's copies between devices. Last: destroyed first, it finishes the copies in
    // flight while the slabs and the staging they read still exist.
    std::unique_ptr<cl_rt::Relay> relay_;
};

}  // namespace clsph::multi
