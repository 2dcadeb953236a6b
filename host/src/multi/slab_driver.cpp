#include "multi/slab_driver.hpp"

#include "clsph/error.hpp"
#include "device/generate.hpp"
#include "device/sizing.hpp"
#include "multi/calibration.hpp"
#include "scene/ghost_nodes.hpp"
#include "scene/motion.hpp"

#include <algorithm>

namespace clsph::multi {

SlabDriver::SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
                       const Particles& p, const DriverOptions& options)
    : feed_(scene, p.size() == 0 ? 0 : 1 + *std::max_element(p.id.begin(), p.id.end())),
      partition_(grid),
      options_(options),
      params_(device::make_sph_params(scene)),
      symplectic_(scene.physics.integrator == Integrator::symplectic) {
    set_up(devices, scene, &p, nullptr);
}

SlabDriver::SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
                       const scene::LatticePlan& plan, const DriverOptions& options)
    : feed_(scene, plan.count()),
      partition_(grid),
      options_(options),
      params_(device::make_sph_params(scene)),
      symplectic_(scene.physics.integrator == Integrator::symplectic) {
    set_up(devices, scene, nullptr, &plan);
}

void SlabDriver::set_up(const std::vector<cl_rt::Device*>& devices, const Scene& scene, const Particles* host,
                        const scene::LatticePlan* plan) {
    const device::Grid& grid = partition_.grid();
    // Passes before the force pass whose results the force pass reads from neighbours (the SPS
    // stress, summation densities) run over the inner halo column too, so it needs its own
    // neighbours: a second halo column (kernels/sps.cl, Physics::forces).
    if (scene.physics.viscosity == Viscosity::laminar_sps || scene.physics.density == DensityMode::summation)
        partition_.set_halo(2);
    // Across ranks: the slabs of rank 0 first, then rank 1's, ...; only this rank's have devices.
    std::size_t first_here = 0;
    std::size_t D = devices.size();
    if (options_.ranks) {
        own_ranks_ = options_.ranks->fork();  // this run's own messages
        ranks_.ranks = own_ranks_.get();
        ranks_.rank = ranks_.ranks->rank();
        const auto counts = own_ranks_->gather_all({static_cast<std::uint64_t>(devices.size())});
        D = 0;
        for (int r = 0; r < ranks_.ranks->size(); ++r) {
            if (r < ranks_.rank) first_here += counts[static_cast<std::size_t>(r)];
            D += counts[static_cast<std::size_t>(r)];
            ranks_.slab_rank.insert(ranks_.slab_rank.end(), counts[static_cast<std::size_t>(r)], r);
        }
    }
    set_up_lists(scene);
    if (options_.inlet_state) feed_.restore(*options_.inlet_state);
    outlet_zones_ = scene::has_outlet_zones(scene);
    // With inlets the count grows: the stores start with room for what the memory plan plans for.
    const std::size_t total = static_cast<std::size_t>(
        scene::planned_with_inlets(scene, host ? host->size() : static_cast<std::size_t>(plan->count())));
    auto say = [&](const std::string& line) {
        if (options_.progress) options_.progress(line);
    };
    balance::Options bo;
    bo.mode = options_.balance;
    // A device may be left idle when even its narrowest slab would slow every step (a CPU next to a
    // GPU); the balancer does so only on a calibration or enough measured steps (balance/options.hpp).
    bo.allow_idle = true;
    balancer_ = std::make_unique<balance::Balancer>(D, partition_.columns(), bo);
    Census census = host ? partition_.census(*host) : partition_.census(*plan);
    slabs_.resize(D);
    for (std::size_t d = 0; d < D; ++d) {
        if (!here(d)) continue;
        Slab& s = slabs_[d];
        s.device = devices[d - first_here];
        const std::size_t capacity = device::sizing::slab_capacity(total, D, options_.headroom);
        s.store = std::make_unique<device::ParticleStore>(*s.device, grid, capacity, options_.headroom);
        s.cells = std::make_unique<device::CellPipeline>(*s.device, grid, !options_.seams.unfused);
        s.cells->set_cell_headroom(options_.cell_headroom);
        s.physics = std::make_unique<device::Physics>(*s.device, grid, scene, options_.interaction);
        s.force_timer = std::make_unique<ForceTimer>(*s.device);
        if (!scene.inlets.empty()) s.inlets = std::make_unique<device::InletZones>(*s.device, grid, scene);
        if (outlet_zones_) s.outlets = std::make_unique<device::OutletZones>(*s.device, grid, scene);
    }
    resolve_cell_order();
    set_up_motion(scene);  // moving and floating solids (multi/slab_floating.cpp)
    if (scene.boundary_method == BoundaryMethod::mdbc) {
        // mDBC: every device holds each boundary particle's ghost-node offset at rest, by id (those
        // of moving solids turn with them: Physics::set_ghost_nodes). Boundaries come first in id
        // order, so a plan's boundary particles alone have the scene's ids. With moving solids, from
        // the scene's particles at rest (a checkpoint's have moved).
        const bool at_rest = (scene.has_motion() || scene.has_floating()) && host;
        const Particles boundary = host && !at_rest ? Particles()
                                   : plan ? plan->particles([](const auto&, std::size_t) { return true; }, true)
                                          : scene.build_particles();
        const Particles& p = host && !at_rest ? *host : boundary;
        const auto offsets = scene::ghost_node_offsets(scene, p);
        std::vector<std::array<float, 3>> by_id;
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (p.type[i] != ParticleType::boundary) continue;
            const std::size_t id = p.id[i] & CLSPH_ID_MASK;
            if (id >= by_id.size()) by_id.resize(id + 1, {0.0f, 0.0f, 0.0f});
            by_id[id] = offsets[i];
        }
        for (std::size_t d = 0; d < D; ++d)
            if (here(d)) slabs_[d].physics->set_ghost_nodes(by_id);
        // The next step's forces read boundary densities each owner computed: the owner must hold
        // the fluid around each of its particles' ghost nodes (Partition::restrict_cuts).
        if (D > 1 && scene.has_motion()) {
            // Moving solids: their particles and ghost nodes wherever the motion takes them.
            const auto swept = scene::swept_ghost_nodes(scene, p, offsets);
            partition_.restrict_cuts(swept.first, swept.second, scene.physics.support());
            census.profile.cut_allowed = partition_.cut_allowed();
        } else if (D > 1) {
            partition_.restrict_cuts(p, offsets, scene.physics.support());
            census.profile.cut_allowed = partition_.cut_allowed();
        }
        if (D > 1 && bodies_) {  // floating bodies: from where they are (multi/slab_floating.cpp)
            set_up_body_cuts(scene, p, offsets);
            keep_cuts_off_bodies(false);
            census.profile.cut_allowed = partition_.cut_allowed();
        }
    }
    // Across ranks each rank times its own devices, and every rank hands every slab's fitted
    // model to its balancer (summed: one rank's figures and the others' zeros), so every rank
    // computes the same first cuts.
    if (D > 1 && bo.mode == balance::Mode::dynamic) {
        say("timing each device on samples of the scene");
        ColumnSampler sample;
        std::vector<std::vector<std::uint32_t>> by_column;
        if (host) {
            const std::uint32_t invalid = grid.params().invalid_key;
            by_column.resize(partition_.columns());
            for (std::size_t i = 0; i < host->size(); ++i)
                if (census.key[i] != invalid) by_column[partition_.column_of(census.key[i])].push_back(static_cast<std::uint32_t>(i));
            sample = [&](std::size_t lo, std::size_t hi) {
                Particles out;
                const Particles& p = *host;
                for (std::size_t c = lo; c < hi; ++c)
                    for (std::uint32_t i : by_column[c])
                        out.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
                return out;
            };
        } else {
            sample = [&](std::size_t lo, std::size_t hi) { return device::slab_particles(*plan, grid, lo, hi); };
        }
        calibrate(slabs_, partition_, sample, total, census, *balancer_);
        if (across_ranks()) share_calibrations(slabs_, *ranks_.ranks, *balancer_);
    }
    std::vector<std::size_t> first{0, partition_.columns()};
    if (D > 1) {
        first = balancer_->initial_cuts(census.profile);
        if (options_.cuts.size() == D + 1 && options_.cuts.back() == partition_.columns()) {
            first = options_.cuts;  // a checkpoint's: the balancer goes on from them
            balancer_->restore_cuts(first);
        }
    }
    if (across_ranks()) {  // every rank computed them alike; rank 0's are the ones
        std::vector<std::uint64_t> c(first.begin(), first.end());
        ranks_.ranks->broadcast(c, 0);
        first.assign(c.begin(), c.end());
    }
    partition_.set_cuts(slabs_, first);
    if (host) {
        const auto parts = partition_.split(*host, census, slabs_);
        for (std::size_t d = 0; d < D; ++d)
            if (here(d)) slabs_[d].store->upload(parts[d]);
    } else {
        for (std::size_t d = 0; d < D; ++d) {
            if (!here(d)) continue;
            Slab& s = slabs_[d];
            if (s.empty()) {
                s.store->ranges = device::ParticleRanges{0, 0, 0};
                continue;
            }
            std::uint64_t n = 0;
            for (auto c : device::slab_counts(*plan, grid, s.first_col, s.end_col)) n += c;
            say("generating " + std::to_string(n) + " particles (grid columns [" + std::to_string(s.first_col) + ", " +
                std::to_string(s.end_col) + ")) on " + s.device->label());
            device::Generator(*s.device, grid).generate(*plan, *s.store, s.first_col, s.end_col);
        }
    }
    say("sorting the particles into cells");
    exchange_ = std::make_unique<Exchange>(partition_, slabs_, [this](const PerDevice& w) { for_each_device(w); },
                                           options_.wait, phases_, options_.seams.wide_exchange, ranks_);
    removed_at_upload_ = exchange_->sort_uploaded();
    // Several devices: the interior's forces while the arrivals travel, where the force pass can be
    // split (no pass before it, no cluster lists) and the tables of the kept particles stay valid
    // (arrival order: the morton order moves particles within cells).
    // Not with serialize_devices: its point is each device's pass timed alone, and the interiors'
    // passes are all enqueued before any device waits.
    if (D > 1 && !options_.seams.whole_force_pass && !options_.seams.serialize_devices) {
        for (std::size_t d = 0; d < D; ++d)
            if (here(d) && slabs_[d].physics->splittable() && slabs_[d].cells->order() == CellOrder::arrival)
                slabs_[d].cells->set_edges_apart(true);  // the interior's forces sit in the scratch
        exchange_->overlap_interior(
            {[this](std::size_t d) { return slabs_[d].cells->edges_apart(); },
             [this](std::size_t d, std::size_t lo, std::size_t hi) { interior_forces(d, lo, hi); }});
    }
    figures_.resize(D);
    for (std::size_t d = 0; d < D; ++d)
        if (here(d)) figures_[d].global_memory = static_cast<std::size_t>(slabs_[d].device->info().global_memory);
    if (across_ranks()) gather_figures();
    if (!options_.balance_log.empty() && ranks_.rank == 0) {
        log_file_ = std::make_unique<std::ofstream>(options_.balance_log);
        if (!*log_file_) throw Error("--balance-log: cannot write " + options_.balance_log);
        log_ = std::make_unique<balance::BalanceLog>(*log_file_, D);
    }
}

StepOutcome SlabDriver::start() {
    start_bodies();  // floating bodies given initial velocities: their particles' before the first forces
    cl_rt::EventSet kicked;
    const Particles* made = created_by(options_.start_time);  // inlets: their buffers, on a new run
    inlet_speeds_ = feed_.speeds(options_.start_time);
    outlet_time_ = options_.start_time;
    const std::size_t removed = exchange_->run(
        [&](std::size_t d) {
            forces(d);
            kick(d, 0.0, kicked);  // dt = 0: the checks, the reductions and a_0 into accel
        },
        made);
    StepOutcome out = reductions(kicked);
    lists_.built();
    last_kick_ = out.kick;
    take_body_forces(0.0);
    out.removed = removed_at_upload_ + removed;
    out.created = made ? made->size() : 0;
    read_force_times();
    return out;
}

// The step, on every device count. One device is the same path: no windows, no neighbours.
StepOutcome SlabDriver::step_here(double dt, double time) {
    // run.list_buffer: the tables of the last build kept, unless a particle may leave their reach
    // in this step; the particles, their order and the cuts stay as they are until the next build.
    const bool build = lists_.due(dt, last_kick_.max_speed2, last_kick_.max_accel2);
    if (build) {
        keep_cuts_off_bodies();                    // mDBC, floating bodies: no cut within their ghost nodes' reach
        apply_seams();                             // tests: forced cuts
        if (steps_ > 0 && slabs_.size() > 1 && !options_.seams.cut_schedule)
            rebalance();                           // cuts from the last step's force times (host only)
    }
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (here(d)) slabs_[d].physics->keep_tables(!build);
    const PerDevice drifted = drift(dt, time);     // first kick and drift, enqueued by the exchange before its settle
    cl_rt::EventSet kicked;
    std::size_t removed = 0;
    const Particles* made = nullptr;
    if (symplectic_) {                             // Symplectic: the predictor was the drift;
        removed += exchange_->run([&](std::size_t d) {  // forces at the half step,
            forces(d);
            correct(d, dt, time);                  // the corrector to the full step;
        }, nullptr, drifted);
        if (bodies_) correct_bodies(dt, time);     // floating bodies: theirs, from every device's sums
        removed += exchange_->run([&](std::size_t d) {  // the positions moved again: forces there
            forces(d);                             // (the next predictor's), and the reductions
            kick(d, 0.0, kicked);
        });
    } else {
        made = created_by(time + dt);              // inlets: the layers due by the step's end,
        inlet_speeds_ = feed_.speeds(time + dt);   // their speeds then; outlet zones: their level then
        outlet_time_ = time + dt;
        const PerDevice then = [&](std::size_t d) {  // after the cell tables, at once on each
            forces(d);                             // device's thread: the force pass, the second
            kick(d, dt, kicked);                   // kick and its reductions
        };
        if (build)
            removed = exchange_->run(then, made, drifted);  // settle, send, merge, cell tables
        else
            exchange_->keep(then, drifted);        // the halos' copies brought up to date
    }
    StepOutcome out = reductions(kicked);         // wait; max |v|, max |a|, energy and bad values over all devices
    if (build)
        lists_.built();
    else
        lists_.kept(dt, last_kick_.max_speed2, last_kick_.max_accel2);
    last_kick_ = out.kick;
    take_body_forces(symplectic_ ? 0.0 : dt);      // floating bodies: the kick (Symplectic: the new accelerations)
    out.removed = removed;
    out.created = made ? made->size() : 0;
    read_force_times();                            // the balancer's input for the next step
    ++steps_;
    return out;
}

void SlabDriver::set_up_lists(const Scene& scene) {
    const double buffer = scene.run.list_buffer;
    if (!(buffer > 0)) return;
    // What moves particles besides the leap-frog drift, whose bound ListSchedule takes, or makes
    // and removes them between sorts.
    const char* why = symplectic_ ? "the Symplectic integrator (its corrector moves particles a second time)"
                      : scene.has_motion()   ? "moving solids"
                      : scene.has_floating() ? "floating bodies"
                      : !scene.inlets.empty() ? "inlets"
                      : scene::has_outlet_zones(scene) ? "outlet zones"
                      : options_.ranks ? "several MPI ranks"
                                       : nullptr;
    if (why)
        throw SceneError("run.list_buffer: tables kept over steps are not supported with " + std::string(why) +
                         " in this version; set run.list_buffer to 0");
    lists_ = ListSchedule(0.5 * buffer * scene.physics.support());
}

void SlabDriver::apply_seams() {
    const auto& seams = options_.seams;
    if (seams.cut_schedule && slabs_.size() > 1) partition_.set_cuts(slabs_, seams.cut_schedule(steps_, columns()));
}

PerDevice SlabDriver::drift(double dt, double time) {
    auto poses = drift_bodies(dt);  // floating bodies: where their particles go (none: empty)
    // Inlets whose speed follows a series: their buffers move by exactly X(t + dt) - X(t).
    const bool ramps = feed_.speeds_vary();
    if (ramps) inlet_means_ = feed_.mean_speeds(time, dt);
    return [this, poses = std::move(poses), ramps, dt, time](std::size_t d) {
        auto& physics = *slabs_[d].physics;
        if (!poses.empty()) physics.set_floating_poses(poses);
        if (ramps && slabs_[d].inlets) slabs_[d].inlets->impose(*slabs_[d].store, inlet_means_, false);
        if (symplectic_)
            physics.predict(*slabs_[d].store, dt);
        else
            physics.kick_drift(*slabs_[d].store, dt);
        physics.move_solids(*slabs_[d].store, time, dt, symplectic_ ? 0.5 : 1.0);  // moving solids: at the drift's time
        if (slabs_[d].outlets) slabs_[d].outlets->remove_past(*slabs_[d].store);  // the settle removes and counts them
    };
}

void SlabDriver::correct(std::size_t d, double dt, double time) {
    Slab& s = slabs_[d];
    s.physics->correct(*s.store, s.store->scratch, dt);
    s.physics->move_solids(*s.store, time, dt, 1.0);
    s.device->flush();
}

void SlabDriver::rebalance() {
    PhaseTimer t(phases_, "balance");
    auto profile = partition_.column_profile(slabs_);
    if (across_ranks()) {  // each column is counted by the one slab that owns it: sum over ranks
        std::vector<double> work = profile.work;
        std::vector<std::uint64_t> particles(profile.particles.begin(), profile.particles.end());
        ranks_.ranks->sum(work);
        ranks_.ranks->sum(particles);
        profile.work = work;
        profile.particles.assign(particles.begin(), particles.end());
    }
    std::vector<balance::DeviceSample> samples;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        const Slab& s = slabs_[d];
        balance::DeviceSample x;
        x.compute_seconds = s.force_seconds;
        for (std::size_t c = s.first_col; c < s.end_col; ++c) x.work += profile.work[c];
        x.particles = here(d) ? s.store->ranges.owned : figures_[d].owned;
        // Capacity: what the device's memory holds at ~100 bytes per particle, leaving a quarter free.
        x.capacity_particles = static_cast<std::size_t>(static_cast<double>(figures_[d].global_memory) * 0.75 / 100.0);
        samples.push_back(x);
    }
    auto decision = balancer_->step(samples, profile);
    if (across_ranks()) {  // the same inputs on every rank; rank 0's cuts are the ones
        std::vector<std::uint64_t> c(decision.cuts.begin(), decision.cuts.end());
        ranks_.ranks->broadcast(c, 0);
        decision.cuts.assign(c.begin(), c.end());
    }
    if (log_) log_->write(steps_, samples, decision);
    partition_.set_cuts(slabs_, decision.cuts);
}

int SlabDriver::force_repeats(std::size_t d) const {
    const auto& slowdown = options_.seams.slowdown;
    return d < slowdown.size() ? std::max(1, slowdown[d]) : 1;
}

void SlabDriver::interior_forces(std::size_t d, std::size_t first, std::size_t last) {
    Slab& s = slabs_[d];
    s.force_timer->begin();  // a new pass; forces(d) adds the rest where the interior's results stand
    for (int k = 0; k < force_repeats(d); ++k) s.physics->forces_part(*s.store, *s.cells, s.store->scratch, first, last);
    s.force_timer->end();
}

void SlabDriver::forces(std::size_t d) {
    Slab& s = slabs_[d];
    auto& ps = *s.store;
    const bool timed = slabs_.size() > 1;  // only the balancer reads the time
    // The interior ran while the arrivals travelled (interior_forces) and its results stand (the
    // exchange says which): the owned particles either side. Otherwise the whole pass, over
    // whatever that one wrote.
    const bool split = s.interior_end > s.interior_first;
    if (timed) s.force_timer->begin(split);
    for (int k = 0; k < force_repeats(d); ++k) {
        if (!split) {
            s.physics->forces(ps, *s.cells, ps.scratch);
            continue;
        }
        s.physics->forces_part(ps, *s.cells, ps.scratch, ps.ranges.first_owned(), s.interior_first);
        s.physics->forces_part(ps, *s.cells, ps.scratch, s.interior_end, ps.ranges.end_owned());
    }
    if (split) {
        s.physics->forces_finish(ps, *s.cells, ps.scratch);
        ++s.split_passes;
        s.interior_first = s.interior_end = 0;
    }
    if (timed) s.force_timer->end();
    if (s.inlets) s.inlets->impose(*s.store, inlet_speeds_, true);  // inlet buffers: their velocity, before the kick
    if (s.outlets) s.outlets->hold(*s.store, outlet_time_);          // outlet zones: their density
    if (options_.seams.serialize_devices) s.device->finish();
}

void SlabDriver::kick(std::size_t d, double dt, cl_rt::EventSet& kicked) {
    Slab& s = slabs_[d];
    if (s.store->ranges.owned > 0) s.physics->enqueue_kick(*s.store, dt, kicked);  // idle devices rest
    s.device->flush();
    // While the force pass runs, the profiler (Options::profile) folds in the step's finished launches.
    if (s.device->profiler().enabled()) s.device->profiler().collect_finished();
}

void SlabDriver::gather_figures() {
    const std::size_t D = slabs_.size();
    std::vector<double> seconds(D, 0.0);
    std::vector<std::uint64_t> counts(2 * D, 0);
    for (std::size_t d = 0; d < D; ++d) {
        if (!here(d)) continue;
        seconds[d] = slabs_[d].force_seconds;
        counts[2 * d] = slabs_[d].store->ranges.owned;
        counts[2 * d + 1] = figures_[d].global_memory;
    }
    ranks_.ranks->sum(seconds);
    ranks_.ranks->sum(counts);
    for (std::size_t d = 0; d < D; ++d) {
        figures_[d] = {seconds[d], static_cast<std::size_t>(counts[2 * d]), static_cast<std::size_t>(counts[2 * d + 1])};
        slabs_[d].force_seconds = seconds[d];
    }
}

void SlabDriver::read_force_times() {
    if (slabs_.size() == 1) return;
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (here(d)) slabs_[d].force_seconds = slabs_[d].force_timer->seconds();
    if (across_ranks()) gather_figures();
}

void SlabDriver::resolve_cell_order() {
    // One order for the whole run, whatever each device runs: the same cell must come out in the
    // same order on any device holding it, or several devices would not be bitwise one.
    CellOrder order = options_.cell_order;
    if (order == CellOrder::automatic) {
        // Morton where every device runs lanes, the form measured to gain from it (docs/interaction.md).
        std::uint64_t others = 0;
        for (std::size_t d = 0; d < slabs_.size(); ++d)
            if (here(d)) others += slabs_[d].physics->interaction() != Interaction::lanes;
        if (ranks_.ranks) {
            std::vector<std::uint64_t> n{others};
            ranks_.ranks->sum(n);
            others = n[0];
        }
        order = others == 0 ? CellOrder::morton : CellOrder::arrival;
    }
    cell_order_ = order;
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (here(d)) slabs_[d].cells->set_order(order);
}

}  // namespace clsph::multi
