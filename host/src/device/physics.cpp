#include "device/physics.hpp"

#include "cl/errors.hpp"
#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"
#include "device/sizing.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>

namespace clsph::device {

SphParams make_sph_params(const Scene& scene) {
    const auto& ph = scene.physics;
    const double pi = 3.14159265358979323846;
    const double h = ph.h(), c0 = scene.sound_speed();
    const double B = c0 * c0 * ph.rho0 / ph.gamma;
    SphParams sp{};
    sp.h = static_cast<float>(h);
    sp.inv_h = static_cast<float>(1.0 / h);
    sp.support2 = static_cast<float>(4.0 * h * h);
    sp.kernel_norm = static_cast<float>(ph.kernel == KernelType::wendland_c2 ? 21.0 / (16.0 * pi * h * h * h)
                                                                             : 1.0 / (pi * h * h * h));
    sp.mass = static_cast<float>(ph.rho0 * ph.dp * ph.dp * ph.dp);
    sp.rho0 = static_cast<float>(ph.rho0);
    sp.inv_rho0 = static_cast<float>(1.0 / ph.rho0);
    sp.eos_b = static_cast<float>(B);
    sp.c0 = static_cast<float>(c0);
    sp.visc_alpha = static_cast<float>(ph.alpha);
    sp.eta2 = static_cast<float>(0.01 * h * h);
    sp.visc_alpha_wall = static_cast<float>(ph.alpha_wall);
    sp.diffusion = static_cast<float>(ph.diffusion == Diffusion::none ? 0.0 : ph.delta * h * c0);
    sp.hydro = static_cast<float>(ph.rho0 * ph.rho0 / (ph.gamma * B));
    sp.gx = static_cast<float>(ph.gravity[0]);
    sp.gy = static_cast<float>(ph.gravity[1]);
    sp.gz = static_cast<float>(ph.gravity[2]);
    sp.rho_min = static_cast<float>(ph.density_min * ph.rho0);
    sp.rho_max = static_cast<float>(ph.density_max * ph.rho0);
    sp.visc_laminar = static_cast<float>(4.0 * ph.kinematic_viscosity);
    sp.sps_smag = static_cast<float>(0.12 * ph.dp * 0.12 * ph.dp);
    sp.sps_blin = static_cast<float>(2.0 / 3.0 * 0.0066 * ph.dp * ph.dp);
    return sp;
}

Interaction interaction_for(Interaction requested, const cl_rt::Device& device) {
    if (requested != Interaction::automatic) return requested;
    return device.info().is_cpu() && !device.quirks().vectorises_work_items ? Interaction::lanes : Interaction::fine;
}

namespace {
// Vector lanes of the CPU form. 16 floats fill an AVX-512 register (CPUs with only AVX2 run them as
// two); on the 2-core EPYC development machine, SPHERIC-2 at dp 0.02: 16 lanes 44 ms, 8 lanes 64 ms
// per force pass (pocl pthread; BENCHMARKS.md).
constexpr std::size_t kLanes = 16;
}  // namespace

Physics::Physics(cl_rt::Device& device, const Grid& grid, const Scene& scene, Interaction form)
    : device_(device),
      grid_(grid),
      sp_(make_sph_params(scene)),
      form_(interaction_for(form, device)),
      summation_(scene.physics.density == DensityMode::summation),
      mdbc_(scene.boundary_method == BoundaryMethod::mdbc),
      no_slip_(mdbc_ && scene.wall_slip == WallSlip::no_slip),
      symplectic_(scene.physics.integrator == Integrator::symplectic),
      wg_(device.work_group_size(128)),
      coarse_wg_(device.work_group_size(64)) {
    std::string opts = grid.kernel_options();
    if (scene.physics.kernel == KernelType::cubic_spline) opts += " -DCLSPH_KERNEL_CUBIC";
    point_options_ = opts;
    const int diffusion = scene.physics.diffusion == Diffusion::none                 ? 0
                          : scene.physics.diffusion == Diffusion::molteni_colagrossi ? 1
                                                                                     : 2;
    std::string interaction = opts + " -DCLSPH_DIFFUSION=" + std::to_string(diffusion);
    if (summation_) interaction += " -DCLSPH_SUMMATION";
    if (mdbc_) interaction += " -DCLSPH_MDBC";
    if (no_slip_) wall_options_ = " -DCLSPH_NOSLIP";  // forces, sps, floating and mdbc (wall_velocity.h)
    interaction += wall_options_;
    if (scene.physics.viscosity != Viscosity::artificial)
        viscosity_options_ = scene.physics.viscosity == Viscosity::laminar ? " -DCLSPH_VISCOSITY=1" : " -DCLSPH_VISCOSITY=2";
    interaction += viscosity_options_;
    switch (form_) {
    case Interaction::lanes: interaction += " -DCLSPH_LANES=" + std::to_string(kLanes); break;
    case Interaction::coarse: interaction += " -DCLSPH_COARSE -DWG=" + std::to_string(coarse_wg_); break;
    case Interaction::clusters:
        // Lists kept over steps (run.list_buffer) hold the clusters within the support plus the
        // buffer: every pair that comes within the support before the next build.
        clusters_ = std::make_unique<ClusterList>(
            device, grid, static_cast<float>(std::pow(scene.physics.support() * (1.0 + scene.run.list_buffer), 2)));
        interaction += clusters_->kernel_options();
        break;
    default: break;
    }
    if (*device.quirks().interaction_options) interaction += std::string(" ") + device.quirks().interaction_options;
    forces_k_ = device.kernel("forces.cl", "forces", interaction);
    if (scene.physics.viscosity == Viscosity::laminar_sps) build_sps(opts + wall_options_);
    if (summation_) density_k_ = device.kernel("density.cl", "summation_density", interaction);
    const std::string integ = opts + " -DWG=" + std::to_string(wg_);
    commit_k_ = device.kernel("integrate.cl", "commit_density", integ);
    kick_drift_k_ = device.kernel("integrate.cl", "kick_drift", integ);
    kick_k_ = device.kernel("integrate.cl", "kick", integ);
    if (symplectic_) {
        predict_k_ = device.kernel("integrate.cl", "symplectic_predict", integ);
        correct_k_ = device.kernel("integrate.cl", "symplectic_correct", integ);
    }
    probe_k_ = device.kernel("probes.cl", "probe_points", opts);
    // mDBC's ghost nodes in the CPU form where the interaction pass runs it (kernels/mdbc_lanes.cl).
    if (mdbc_ && form_ == Interaction::lanes)
        mdbc_k_ = device.kernel("mdbc_lanes.cl", "mdbc_boundary_lanes",
                                opts + wall_options_ + " -DCLSPH_LANES=" + std::to_string(kLanes));
    else if (mdbc_)
        mdbc_k_ = device.kernel("mdbc.cl", "mdbc_boundary", opts + wall_options_);
    probe_counted_k_ = device.kernel("probes.cl", "probe_points_counted", opts);
    kick_groups_ = sizing::kick_groups(device.info().compute_units);
    partials_ = device.alloc(kick_groups_ * sizing::kKickFloats * sizeof(float), "kick reductions");
    bad_ = device.alloc(sizeof(cl_uint), "failure flag");
    dt_f_ = device.alloc(sizeof(float), "time step");
    halt_ = device.alloc(sizeof(cl_uint), "halt flag");
    device.fill(halt_, cl_uint{0}, 1);
    cfl_ = scene.physics.cfl;
    dt_viscous_ = scene.physics.viscous_dt();
    fixed_dt_ = scene.run.fixed_dt;
    const std::string ext = device.cl_device().getInfo<CL_DEVICE_EXTENSIONS>();
    has_clock_ = ext.find("cl_khr_fp64") != std::string::npos;
    if (has_clock_) {
        clock_wg_ = device.work_group_size(64);  // one work-group stages the kick's partials (step_clock.cl)
        end_k_ = device.kernel("step_clock.cl", "end_step", "-DCLOCK_WG=" + std::to_string(clock_wg_));
        sums_k_ = device.kernel("step_clock.cl", "step_sums", "-DCLOCK_WG=" + std::to_string(clock_wg_));
        clock_ = device.alloc(sizing::kClockDoubles * sizeof(double), "step clock");
        device.fill(bad_, cl_uint{0xffffffffu}, 1);
    }
}

namespace {
// Arguments common to every interaction kernel of neighbour_loop.h (the clusters form's lists
// after the ranges), for particles [first, last); returns the index of the interaction file's
// first argument after sp.
cl_uint set_loop_args(cl::Kernel& k, std::size_t first, std::size_t last, const ParticleStore& ps,
                      const CellPipeline& cells, const GridParams& g, const SphParams& sp, bool per_cell,
                      const ClusterList* clusters) {
    k.setArg(0, static_cast<cl_uint>(first));
    k.setArg(1, static_cast<cl_uint>(last));
    k.setArg(2, g);
    k.setArg(3, sp.support2);
    k.setArg(4, ps.pos.get());
    k.setArg(5, per_cell ? cells.cell_start().get() : ps.vals.get());
    k.setArg(6, cells.ranges().get());
    cl_uint a = 7;
    if (clusters) {
        k.setArg(a++, cells.cell_start().get());
        k.setArg(a++, clusters->begins().get());
        k.setArg(a++, clusters->masks().get());
    }
    k.setArg(a++, sp);
    return a;
}
}  // namespace

void Physics::launch_interaction(const char* name, cl::Kernel& k, const CellPipeline& cells, std::size_t count) {
    if (form_ == Interaction::coarse)
        device_.launch(name, k, cells.cells() * coarse_wg_, coarse_wg_);
    else if (form_ == Interaction::lanes)
        device_.launch(name, k, cells.cells(), 1);  // a work-item per cell, nothing to pad
    else
        device_.launch(name, k, count, wg_);
}

void Physics::forces(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out) {
    const std::size_t n = ps.ranges.owned;
    floating_summed_ = false;  // the bodies' sums of an earlier pass (the calibration's) are not this one's
    if (n == 0) return;
    const auto g = grid_.params();
    // Summation densities of every particle held, ghosts included: the force pass reads those of
    // the inner halo column, whose neighbours the second halo column holds (SlabDriver::set_up). The
    // outer column's are incomplete and never read; the next exchange replaces all ghosts. So the
    // forces see the step's densities on every device count, as on one device (issue 33's find).
    const std::size_t first = summation_ ? 0 : ps.ranges.first_owned();
    const std::size_t last = summation_ ? ps.ranges.active() : ps.ranges.end_owned();
    if (clusters_ && !tables_kept_) clusters_->build(ps, cells, first, last);  // on new tables
    if (summation_) {
        const cl_uint a = set_loop_args(density_k_, first, last, ps, cells, g, sp_, per_cell(), clusters_.get());
        density_k_.setArg(a, ps.velrho.get());
        density_k_.setArg(a + 1, ps.id.get());
        density_k_.setArg(a + 2, ps.scratch.get());  // free between reorders: new densities
        launch_interaction("sph.density", density_k_, cells, last - first);
        commit_k_.setArg(0, static_cast<cl_uint>(first));
        commit_k_.setArg(1, static_cast<cl_uint>(last));
        commit_k_.setArg(2, ps.scratch.get());
        commit_k_.setArg(3, ps.velrho.get());
        device_.launch("sph.commit_density", commit_k_, last - first, wg_);
    }
    if (sps_) sps_stress(ps, cells);  // with the step's final densities
    launch_forces(ps, cells, out, ps.ranges.first_owned(), ps.ranges.end_owned());
    forces_finish(ps, cells, out);
}

void Physics::forces_part(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out, std::size_t first,
                          std::size_t last) {
    if (!splittable()) throw Error("the force pass cannot be split with this scene's passes before it");
    floating_summed_ = false;
    if (last > first) launch_forces(ps, cells, out, first, last);
}

void Physics::launch_forces(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out, std::size_t first,
                            std::size_t last) {
    const cl_uint a = set_loop_args(forces_k_, first, last, ps, cells, grid_.params(), sp_, per_cell(), clusters_.get());
    forces_k_.setArg(a, ps.velrho.get());
    forces_k_.setArg(a + 1, ps.id.get());
    forces_k_.setArg(a + 2, out.get());
    if (sps_) forces_k_.setArg(a + 3, tau_.get());
    if (no_slip_) {
        // The boundary particles' v_wall - v_G of the last pass (kernels/wall_velocity.h): read
        // from accel while this pass writes `out`, which must be another buffer.
        if (&out == &ps.accel) throw Error("no-slip walls: the force pass cannot write into the accelerations it reads");
        forces_k_.setArg(a + (sps_ ? 4 : 3), ps.accel.get());
    }
    launch_interaction("sph.forces", forces_k_, cells, last - first);
}

void Physics::forces_finish(ParticleStore& ps, const CellPipeline& cells, cl_rt::Buffer& out) {
    if (ps.ranges.owned == 0) return;
    // Floating bodies: the fluid's force on them from the boundary densities the fluid has just
    // felt, before the mDBC pass replaces those with the next step's.
    if (floating_bodies_ > 0) enqueue_floating(ps, cells);
    if (mdbc_) boundary_densities(ps, cells, out);
}

void Physics::kick_drift(ParticleStore& ps, double dt) {
    write_dt(dt);
    kick_drift_on_clock(ps);
}

void Physics::kick_drift_on_clock(ParticleStore& ps) {
    const std::size_t n = ps.ranges.owned;
    if (n == 0) return;
    cl_rt::set_args(kick_drift_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), dt_f_, sp_.rho0,
                    grid_.params().invalid_key, ps.pos, ps.velrho, ps.accel, ps.id, halt_);
    device_.launch("sph.kick_drift", kick_drift_k_, n, wg_);
}

void Physics::predict(ParticleStore& ps, double dt) {
    write_dt(dt);
    const std::size_t n = ps.ranges.owned;
    if (n == 0) return;
    cl_rt::set_args(predict_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), dt_f_, sp_.rho0,
                    grid_.params().invalid_key, ps.pos, ps.velrho, ps.accel, ps.id, halt_);
    device_.launch("sph.symplectic_predict", predict_k_, n, wg_);
}

void Physics::correct(ParticleStore& ps, const cl_rt::Buffer& half, double dt) {
    write_dt(dt);
    const std::size_t n = ps.ranges.owned;
    if (n == 0) return;
    cl_rt::set_args(correct_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), dt_f_, sp_.rho0,
                    grid_.params().invalid_key, ps.pos, ps.velrho, ps.accel, half, ps.id, halt_);
    device_.launch("sph.symplectic_correct", correct_k_, n, wg_);
}

void Physics::enqueue_kick(ParticleStore& ps, double dt, cl_rt::EventSet& done) {
    const cl_uint none = 0xffffffffu;
    device_.fill(bad_, none, 1);
    write_dt(dt);
    enqueue_kick_on_clock(ps);
    partials_host_.resize(device_, kick_groups_ * 4);
    std::fill(partials_host_.data(), partials_host_.data() + kick_groups_ * 4, 0.0f);
    bad_host_.resize(device_, 1);
    bad_host_[0] = none;
    device_.read_async(partials_, partials_host_.data(), kick_groups_ * 4 * sizeof(float), 0, done);
    device_.read_async(bad_, bad_host_.data(), sizeof(cl_uint), 0, done);
}

void Physics::write_dt(double dt) {
    const float f = static_cast<float>(dt);
    if (f == dt_written_ && dt_written_valid_) return;  // the kick of a step reuses its drift's
    device_.fill(dt_f_, f, 1);  // the pattern is copied at once: nothing to keep
    dt_written_ = f;
    dt_written_valid_ = true;
}

void Physics::enqueue_kick_on_clock(ParticleStore& ps) {
    cl_rt::set_args(kick_k_, ps.ranges.first_owned(), ps.ranges.end_owned(), dt_f_, sp_, grid_.params().invalid_key,
                    ps.pos, ps.velrho, ps.accel, ps.scratch, ps.id, partials_, bad_, halt_);
    device_.launch("sph.kick", kick_k_, kick_groups_ * wg_, wg_);
    ps.accel.swap(ps.scratch);
}

void Physics::set_clock(double time, double next_dt, double event, double moved) {
    // The first step's dt as end_step computes the ones after it (and run_until on the host).
    const double dt = std::min(next_dt, std::max(event - time, 1e-12));
    clock_host_.resize(device_, sizing::kClockDoubles);
    clock_host_[0] = time;
    clock_host_[1] = dt;
    clock_host_[2] = next_dt;
    clock_host_[3] = event;
    clock_host_[4] = moved;  // run.list_buffer: the bound on any particle's move since the tables were built
    device_.write(clock_, clock_host_.data(), sizing::kClockDoubles);
    const float f = static_cast<float>(dt);
    device_.write(dt_f_, &f, 1);
    dt_written_valid_ = false;  // the clock writes dt_f from here on
    clear_halt();
}

void Physics::set_slabs(std::size_t slabs, std::size_t slots) {
    slabs_ = slabs > 1 ? slabs : 0;
    if (slabs_ == 0 || sums_.bytes() >= slabs_ * slots * kStepSumBytes) return;
    sums_ = cl_rt::Buffer();
    sums_ = device_.alloc(slabs_ * slots * kStepSumBytes, "step sums of every device");
}

void Physics::enqueue_step_sums(std::size_t slot, std::size_t self) {
    cl_rt::set_args(sums_k_, kick_groups_, partials_, bad_, sums_, slot * slabs_ + self);
    device_.launch("clock.sums", sums_k_, clock_wg_, clock_wg_);
}

void Physics::clear_halt() { device_.fill(halt_, cl_uint{0}, 1); }

void Physics::enqueue_end_step(const ParticleStore& ps, const CellPipeline& cells, std::size_t slot, double* record,
                               cl_rt::EventSet& done) {
    const std::size_t bytes = StepRecord::kDoubles * sizeof(double);
    if (record_.bytes() < (slot + 1) * bytes) {
        record_ = cl_rt::Buffer();
        record_ = device_.alloc((slot + 1) * bytes, "step records");
    }
    cl_uint i = 0;
    end_k_.setArg(i++, static_cast<cl_uint>(kick_groups_));
    end_k_.setArg(i++, cfl_);
    end_k_.setArg(i++, static_cast<double>(sp_.h));
    end_k_.setArg(i++, static_cast<double>(sp_.c0));
    end_k_.setArg(i++, fixed_dt_);
    end_k_.setArg(i++, dt_floor_);
    end_k_.setArg(i++, dt_viscous_);
    end_k_.setArg(i++, half_buffer_);
    for (const cl_rt::Buffer* b : std::initializer_list<const cl_rt::Buffer*>{
             &partials_, &bad_, &ps.id, &ps.velrho, &cells.settle_counters(), &cells.cell_count(), &clock_, &dt_f_,
             &halt_, &record_})
        end_k_.setArg(i++, b->get());
    end_k_.setArg(i++, cl_rt::checked_uint(slot));
    if (slabs_ > 0 && sums_.bytes() == 0) throw Error("end_step: the step sums were not set up (set_slabs)");
    end_k_.setArg(i++, slabs_ > 0 ? sums_.get() : halt_.get());  // (any buffer where none is read)
    end_k_.setArg(i++, cl_rt::checked_uint(slabs_));
    device_.launch("clock.end", end_k_, clock_wg_, clock_wg_);
    // The record comes back on the transfer queue, after a marker: the compute queue goes on with
    // the next step instead of waiting for the copy (each slot has its own record on the device,
    // which the host reads before it enqueues the step that writes that slot again).
    cl::Event marker, read;
    cl_rt::check(device_.queue().enqueueMarkerWithWaitList(nullptr, &marker), "marking a step's end", device_.label());
    const std::vector<cl::Event> after{marker};
    cl_rt::check(device_.transfer_queue().enqueueReadBuffer(record_.get(), CL_FALSE, slot * bytes, bytes, record, &after,
                                                            &read),
                 "reading a step's record", device_.label());
    done.add(device_, std::move(read));
    cl_rt::check(device_.transfer_queue().flush(), "submitting the transfer queue", device_.label());
}

StepRecord StepRecord::from(const double* r) {
    StepRecord s;
    s.time = r[0];
    s.dt = r[1];
    s.kick.max_speed2 = r[2];
    s.kick.max_accel2 = r[3];
    s.kick.kinetic_energy = r[4];
    s.next_dt = r[5];
    s.halt = static_cast<unsigned>(r[6]);
    s.kick.bad_index = static_cast<std::int64_t>(r[7]);
    s.bad_id = static_cast<std::uint32_t>(r[8]);
    for (int k = 0; k < 4; ++k) s.bad_velrho[k] = static_cast<float>(r[9 + k]);
    s.left_domain = static_cast<std::size_t>(r[13]);
    s.jumped = static_cast<std::size_t>(r[14]);
    s.cells = static_cast<std::size_t>(r[15]);
    s.kick.fluid = static_cast<std::size_t>(r[16]);
    return s;
}

KickResult Physics::kick_result() const {
    KickResult r;
    if (partials_host_.size() < kick_groups_ * 4 || bad_host_.empty()) return r;  // no kick enqueued yet
    for (std::size_t g = 0; g < kick_groups_; ++g) {
        r.max_speed2 = std::max(r.max_speed2, static_cast<double>(partials_host_[4 * g]));
        r.max_accel2 = std::max(r.max_accel2, static_cast<double>(partials_host_[4 * g + 1]));
        r.kinetic_energy += partials_host_[4 * g + 2];
        r.fluid += static_cast<std::size_t>(partials_host_[4 * g + 3]);
    }
    if (bad_host_[0] != 0xffffffffu) r.bad_index = bad_host_[0];
    return r;
}

std::vector<float> Physics::probe_query(const std::vector<std::array<double, 3>>& points) const {
    std::vector<float> q(4 * points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::array<float, 3> off{};
        const std::uint32_t key = grid_.locate(points[i], off);
        std::memcpy(&q[4 * i], off.data(), sizeof off);
        std::memcpy(&q[4 * i + 3], &key, sizeof key);
    }
    return q;
}

void Physics::set_probe_points(const std::vector<std::array<double, 3>>& points) {
    fixed_points_ = points.size();
    if (points.empty()) return;
    const std::vector<float> q = probe_query(points);
    fixed_in_ = device_.alloc(q.size() * sizeof(float), "probe points (fixed)");
    fixed_out_ = device_.alloc(points.size() * 2 * sizeof(float), "probe sums (fixed)");
    device_.write(fixed_in_, q.data(), q.size());
}

void Physics::enqueue_probe(ParticleStore& ps, const CellPipeline& cells, float* out, cl_rt::EventSet& done) {
    if (fixed_points_ == 0) return;
    cl_rt::set_args(probe_counted_k_, fixed_points_, cells.cell_count(), grid_.params(), sp_, fixed_in_,
                    cells.cell_key(), cells.cell_start(), ps.pos, ps.velrho, ps.id, fixed_out_);
    device_.launch("probe.points", probe_counted_k_, fixed_points_, wg_);
    device_.read_async(fixed_out_, out, fixed_points_ * 2 * sizeof(float), 0, done);
}

std::vector<std::array<float, 2>> Physics::probe(ParticleStore& ps, const CellPipeline& cells,
                                                 const std::vector<std::array<double, 3>>& points) {
    std::vector<std::array<float, 2>> out(points.size());
    if (points.empty()) return out;
    const std::vector<float> q = probe_query(points);
    if (probe_in_.bytes() < q.size() * sizeof(float)) {
        probe_in_ = device_.alloc(q.size() * sizeof(float), "probe points");
        probe_out_ = device_.alloc(points.size() * 2 * sizeof(float), "probe sums");
    }
    device_.write(probe_in_, q.data(), q.size());
    cl_rt::set_args(probe_k_, points.size(), cells.cells(), grid_.params(), sp_, probe_in_, cells.cell_key(),
                    cells.cell_start(), ps.pos, ps.velrho, ps.id, probe_out_);
    device_.launch("probe.points", probe_k_, points.size(), wg_);
    std::vector<float> raw(2 * points.size());
    device_.read(probe_out_, raw.data(), raw.size());
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = {raw[2 * i], raw[2 * i + 1]};
    return out;
}

}  // namespace clsph::device
