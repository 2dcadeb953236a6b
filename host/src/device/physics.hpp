// The WCSPH physics of one device: the constants (SphParams), the force pass (and the summation
// density pass), Leap-frog kicks with the reductions that choose the next time step, and probes.
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "clsph/interaction.hpp"
#include "clsph/scene.hpp"
#include "device/cell_pipeline.hpp"
#include "device/cluster_list.hpp"
#include "device/floating_table.hpp"
#include "device/grid.hpp"
#include "device/motion_table.hpp"
#include "device/particle_store.hpp"
#include "device/sizing.hpp"

#include <array>
#include <memory>
#include <vector>

namespace clsph::device {

SphParams make_sph_params(const Scene& scene);

// The form a device runs when asked for `requested`: automatic becomes lanes on CPU devices whose
// compiler does not vectorise across work-items (pocl: "loop control flow is not understood by
// vectorizer" on the fine loop) and fine elsewhere (GPUs, rusticl: cl/quirks.hpp); the rest stay.
Interaction interaction_for(Interaction requested, const cl_rt::Device& device);

struct KickResult {
    double max_speed2 = 0, max_accel2 = 0, kinetic_energy = 0;
    std::size_t fluid = 0;
    std::int64_t bad_index = -1;  // a particle that failed the checks, or -1
};

// One step as the device's clock recorded it (kernels/step_clock.cl, end_step), read by the host
// a few steps later.
struct StepRecord {
    static constexpr std::size_t kDoubles = sizing::kStepRecordDoubles;
    double time = 0, dt = 0, next_dt = 0;  // after the step; the step; the next CFL step (unclamped)
    KickResult kick;
    unsigned halt = 0;                    // non-zero: the step changed nothing (kHalt*)
    std::uint32_t bad_id = 0;             // with kick.bad_index: the particle's id word and velrho
    float bad_velrho[4] = {0, 0, 0, 0};
    std::size_t left_domain = 0, jumped = 0, cells = 0;  // from settle and the bounded tables
    static StepRecord from(const double* raw);
};
// kHaltLists: run.list_buffer, the next step must build the cell tables (the host takes it).
constexpr unsigned kHaltEvent = 1, kHaltBad = 2, kHaltCells = 4, kHaltLists = 8;

class Physics {
public:
    // `form`: the interaction form to run; automatic picks one by device type (interaction_for).
    Physics(cl_rt::Device& device, const Grid& grid, const Scene& scene, Interaction form = Interaction::automatic);
    const SphParams& params() const { return sp_; }
    // Build options of kernels that evaluate SPH sums at points (probes, the free surface).
    const std::string& point_options() const { return point_options_; }
    Interaction interaction() const { return form_; }  // the form this device runs (never automatic)
    // The clusters form's lists (null for the other forms): built before every forces() on new
    // tables, kept with the tables (keep_tables).
    const ClusterList* cluster_list() const { return clusters_.get(); }
    // run.list_buffer: the next passes run on the tables of the last build (the particles in the
    // same places, moved less than half the buffer): the cluster lists built for them stand.
    void keep_tables(bool kept) { tables_kept_ = kept; }

    // Accelerations and drho/dt of the owned particles into `out` (summation mode: densities
    // first, through ps.scratch). The step writes them to ps.scratch; kick() then makes them
    // ps.accel. With floating bodies, then the fluid's force on them (enqueue_floating); with
    // mDBC, then the owned boundary particles' densities from their ghost nodes (kernels/mdbc.cl),
    // in place: the next step's forces use them (the bodies' force used the same densities as
    // the fluid's). With no-slip walls the passes read the boundary particles' v_wall - v_G from
    // ps.accel, and the mDBC pass writes the next into `out` (kernels/wall_velocity.h): `out`
    // may not be ps.accel then.
    void forces(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out);
    // forces() in parts, for the halo overlapped with the interior (several devices): the force
    // launch alone over particles [first, last), then, once every owned particle had its part,
    // what forces() runs after that launch (floating bodies, mDBC). Only where splittable(): no
    // pass before the force launch (summation density, SPS stress) and no cluster lists, which
    // need every owned particle's tables at once.
    bool splittable() const { return !summation_ && !sps_ && !clusters_; }
    void forces_part(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out, std::size_t first,
                     std::size_t last);
    void forces_finish(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out);
    // mDBC: each boundary particle's offset to its ghost node, by id (scene/ghost_nodes.hpp), at
    // rest; with a motion (set_motion first) the offsets of moving solids turn with them before
    // each mDBC pass (kernels/motion.cl, turn_ghost_nodes).
    bool mdbc() const { return mdbc_; }
    void set_ghost_nodes(const std::vector<std::array<float, 3>>& by_id);
    // The mDBC pass alone (forces() runs it; physics_mdbc.cpp). With no-slip walls it also writes
    // each owned boundary particle's v_wall - v_G into the xyz of `wall_seen` (kernels/mdbc.cl;
    // ps.scratch when not given), keeping w.
    bool no_slip() const { return no_slip_; }
    void boundary_densities(ParticleStore& ps, const CellPipeline& cells);
    void boundary_densities(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& wall_seen);
    // laminar+sps (kernels/sps.cl): every held particle's sub-particle-scale stress into tau()
    // (forces() runs it first; ghosts of the inner halo column get their owner's bits).
    bool sps() const { return sps_; }
    void sps_stress(ParticleStore& ps, const CellPipeline& cells);
    const cl_rt::Buffer& tau() const { return tau_; }  // 2 float4 a particle
    void kick_drift(ParticleStore& ps, double dt);
    // Prescribed motion (kernels/motion.cl): the table uploaded once (every slab holds all of it,
    // by boundary id); then after each drift the owned boundary particles of moving solids put at
    // time + fraction dt (the synchronous path: the host's time before the step and its dt), or at
    // the device's clock's time plus its dt (the step ahead). Nothing without a motion. In double
    // where the device has cl_khr_fp64, else in float.
    void set_motion(const MotionTable& table);
    bool moves() const { return motion_segments_ > 0; }
    void move_solids(ParticleStore& ps, double time, double dt, double fraction);
    void move_solids_on_clock(ParticleStore& ps);
    // Floating bodies (kernels/floating.cl; after set_motion with the table add_floating filled):
    // the body particles' table; before each move of the solids the bodies' poses (RigidBodies::
    // poses) into their rows of the motion table; in each force pass (forces() calls it), the
    // fluid's force on the owned body particles and their fixed-point partial sums enqueued, and
    // read, blocking, added into `sums` (12 a body, wrapping: two's complement). The ghost-node
    // offsets of mDBC turn with a body's orientation (its row's R, turn_ghost_nodes).
    void set_floating(const FloatingTable& table);
    bool floats() const { return floating_bodies_ > 0; }
    void set_floating_poses(const std::vector<std::array<double, 18>>& poses);
    void enqueue_floating(ParticleStore& ps, const CellPipeline& cells);
    void add_floating_sums(std::vector<std::int64_t>& sums);
    cl_rt::Buffer& floating_force() { return floating_force_; }        // tests: per particle
    cl_rt::Buffer& floating_partials() { return floating_partials_; }  // tests: per body and group
    std::size_t floating_partial_count() const { return floating_bodies_ * floating_groups_ * 12; }
    // Symplectic (kernels/integrate.cl): the predictor to the half step (accel holds a_n), and,
    // after the half step's force pass wrote `half` (ps.scratch), the corrector to the full step.
    bool symplectic() const { return symplectic_; }
    void predict(ParticleStore& ps, double dt);
    void correct(ParticleStore& ps, const cl_rt::Buffer& half, double dt);
    // The step ahead: the same first kick with the dt the device's clock chose (begin_step).
    void kick_drift_on_clock(ParticleStore& ps);
    // The second kick: combines the old (ps.accel) and new (ps.scratch) accelerations, then swaps
    // them so ps.accel holds the new ones; the reductions are read into `done`, and after the wait
    // kick_result() has them.
    void enqueue_kick(ParticleStore& ps, double dt, cl_rt::EventSet& done);
    KickResult kick_result() const;
    // The second kick without reading its reductions back (the step ahead: end_step reads them).
    void enqueue_kick_on_clock(ParticleStore& ps);

    // The device's clock (kernels/step_clock.cl): needs cl_khr_fp64, so that it takes the host's
    // steps bitwise. set_clock: time, the next CFL step and the event to land on (the first step's
    // dt from them; end_step chooses each next one); clears the halt.
    bool has_clock() const { return has_clock_; }
    void set_clock(double time, double next_dt, double event, double moved = 0.0);
    void clear_halt();
    // The reductions, the clock advanced, the record of ring slot `slot` read into `record`
    // (StepRecord::kDoubles doubles of pinned memory that must stay put until `done` is waited for).
    void enqueue_end_step(const ParticleStore& ps, const CellPipeline& cells, std::size_t slot, double* record,
                          cl_rt::EventSet& done);
    // The step ahead on several devices (docs/multi_device.md): `slabs` devices, `slots` steps in
    // flight. Each device's step_sums (kernels/step_clock.cl) after its kick puts its part of the
    // reductions at step_sums()[slot * slabs + self]; the other devices' parts are copied in before
    // end_step, which then takes the step every device takes. slabs 0: one device, no copies.
    void set_slabs(std::size_t slabs, std::size_t slots);
    void enqueue_step_sums(std::size_t slot, std::size_t self);
    cl_rt::Buffer& step_sums() { return sums_; }
    static constexpr std::size_t kStepSumBytes = 4 * sizeof(float);
    // run.list_buffer: half the buffer, m (0: off); end_step halts with kHaltLists before a step
    // that must build the tables (multi/list_schedule.hpp: the same bound), which set_clock starts
    // from `moved` (the host's ListSchedule::moved()).
    void set_half_buffer(double half) { half_buffer_ = half; }
    const cl_rt::Buffer& halt() const { return halt_; }
    // The step ahead's first kick and drift as the cell pass runs it in its first launch
    // (CellPipeline::enqueue_drift_sort_keys): the clock's dt, rho0, the halt flag.
    Drift drift_on_clock() const { return Drift{dt_f_, sp_.rho0, halt_}; }
    // A next CFL step below this halts the steps after it (the host stops there: a collapse).
    void set_dt_floor(double dt) { dt_floor_ = dt; }

    // The step ahead: the probe points, fixed for the run; after a probe step, their sums enqueued
    // and read into `out` (2 floats a point, pinned) once `done` is waited for.
    void set_probe_points(const std::vector<std::array<double, 3>>& points);
    void enqueue_probe(ParticleStore& ps, const CellPipeline& cells, float* out, cl_rt::EventSet& done);
    std::size_t probe_points() const { return fixed_points_; }
    // Per probe point: (sum V W, sum p V W) over fluid neighbours. Blocking.
    std::vector<std::array<float, 2>> probe(ParticleStore& ps, const CellPipeline& cells,
                                            const std::vector<std::array<double, 3>>& points);

private:
    // The forms whose kernels take a work-item (lanes) or a work-group (coarse) per cell.
    bool per_cell() const { return form_ == Interaction::coarse || form_ == Interaction::lanes; }
    // An interaction kernel's launch: a work-item per particle of `count`, per cell, or a work-group per cell.
    void launch_interaction(const char* name, cl::Kernel& k, const CellPipeline& cells, std::size_t count);
    void launch_forces(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out, std::size_t first,
                       std::size_t last);
    cl_rt::Device& device_;
    const Grid& grid_;
    SphParams sp_{};
    std::string point_options_;
    std::string viscosity_options_;  // -DCLSPH_VISCOSITY=... for the laminar models (forces.cl, floating.cl)
    bool sps_ = false;
    void build_sps(const std::string& options);
    cl::Kernel sps_k_;
    cl_rt::Buffer tau_;
    Interaction form_;
    bool summation_;
    bool mdbc_;
    bool no_slip_;              // mDBC no-slip walls (boundaries.slip)
    std::string wall_options_;  // -DCLSPH_NOSLIP for forces, sps, floating and mdbc
    bool symplectic_;
    cl::Kernel predict_k_, correct_k_;
    cl::Kernel mdbc_k_;
    cl_rt::Buffer ghost_;
    cl::Kernel motion_k_, turn_k_;
    cl_rt::Buffer motion_table_, motion_rest_, motion_local_, ghost_rest_;
    std::size_t motion_segments_ = 0, motion_ids_ = 0;
    bool motion_float_ = false;
    // The time the last move_solids put the solids at (mDBC turns the ghost nodes to it).
    struct MotionTime { bool on_clock = false; double time = 0, dt = 0, fraction = 1; } motion_time_;
    void launch_motion(ParticleStore& ps, bool on_clock, double time, double dt, double fraction);
    void set_motion_time_args(cl::Kernel& k, cl_uint first_arg) const;  // the clock and the times
    void turn_ghost_nodes(ParticleStore& ps);
    std::size_t ghost_count_ = 0;
    cl::Kernel floating_k_, floating_sums_k_;
    cl_rt::Buffer floating_rest_, floating_force_, floating_partials_;
    std::size_t floating_bodies_ = 0, floating_ids_ = 0, floating_row_ = 0, floating_groups_ = 0, floating_capacity_ = 0;
    bool floating_summed_ = false;  // enqueue_floating ran since the last add_floating_sums
    std::size_t wg_, coarse_wg_, kick_groups_;
    std::unique_ptr<ClusterList> clusters_;
    bool tables_kept_ = false;
    cl::Kernel forces_k_, density_k_, commit_k_, kick_drift_k_, kick_k_, probe_k_;
    cl_rt::Buffer partials_, bad_, probe_in_, probe_out_;
    cl_rt::Buffer dt_f_, halt_, clock_, record_;
    cl::Kernel end_k_, sums_k_, probe_counted_k_;
    cl_rt::Buffer sums_;
    std::size_t slabs_ = 0;
    double half_buffer_ = 0;
    std::size_t clock_wg_ = 1;  // the clock kernel's work-group
    cl_rt::Buffer fixed_in_, fixed_out_;
    std::size_t fixed_points_ = 0;
    std::vector<float> probe_query(const std::vector<std::array<double, 3>>& points) const;
    bool has_clock_ = false;
    void write_dt(double dt);  // the synchronous path: dt_f from the host
    float dt_written_ = 0;
    bool dt_written_valid_ = false;
    double cfl_ = 0, fixed_dt_ = 0, dt_floor_ = 0, dt_viscous_ = 0;
    cl_rt::PinnedArray<double> clock_host_;
    // Read targets of enqueue_kick, in pinned memory (the host waits for them every step).
    cl_rt::PinnedArray<float> partials_host_;
    cl_rt::PinnedArray<cl_uint> bad_host_;
};

}  // namespace clsph::device
