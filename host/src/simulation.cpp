// The facade behind clsph::Simulation: scene -> particles -> device pipeline -> steps.
#include "simulation_impl.hpp"

#include "cl/errors.hpp"
#include "device/memory_census.hpp"
#include "multi/rank_devices.hpp"
#include "multi/ranks.hpp"
#include "render/scene_image.hpp"
#include "surface/extract.hpp"
#include "clsph/memory_plan.hpp"
#include "clsph/testing.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <algorithm>
#include <cstring>
#include <sstream>
#include <exception>
#include <thread>
#include <unordered_map>

#include "clsph/version.hpp"

namespace clsph {

void Simulation::Impl::fail(const multi::StepOutcome& k) {
    if (!driver->here(k.bad_slab))
        throw SimulationError("step " + std::to_string(info.step + 1) + ": a particle of slab " + std::to_string(k.bad_slab) +
                              ", on another MPI rank, went bad (that rank's message names it). The run stopped; the last "
                              "good state is at t = " + std::to_string(last_good_time) + " s.");
    auto& slab = driver->slabs()[k.bad_slab];
    auto& d = *slab.device;
    const auto index = static_cast<std::size_t>(k.kick.bad_index);
    cl_uint id = 0;
    float vr[4] = {0, 0, 0, 0};
    d.read(slab.store->id, &id, 1, index);
    d.read(slab.store->velrho, vr, 4, 4 * index);
    fail_with(id, vr, dt_next, driver->slabs().size() > 1 ? d.label() : std::string());
}

void Simulation::Impl::one_process(const char* what) const {
    if (driver->across_ranks())
        throw Error(std::string(what) + " across MPI ranks are not supported yet (issue 21); run in one process for them");
}

void Simulation::Impl::fail_with(std::uint32_t id, const float vr[4], double dt, const std::string& device) {
    std::ostringstream o;
    const bool fluid = (id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;
    o << "step " << info.step + 1 << ", t = " << info.time + dt << " s: particle " << (id & CLSPH_ID_MASK) << " ("
      << (fluid ? "fluid" : "boundary") << ") ";
    if (!std::isfinite(vr[0]) || !std::isfinite(vr[1]) || !std::isfinite(vr[2]) || !std::isfinite(vr[3]))
        o << "has a non-finite velocity or density";
    else
        o << "has density " << vr[3] << " kg/m^3, outside the allowed band [" << driver->params().rho_min << ", "
          << driver->params().rho_max << "]";
    if (!device.empty()) o << " on device " << device;
    o << " (time step " << dt << " s). The run stopped; the last good state is at t = " << last_good_time << " s.";
    throw SimulationError(o.str());
}

void Simulation::Impl::check_dt_collapse() {
    if (scene.run.fixed_dt > 0) return;
    const auto& sp = driver->params();
    const double acoustic = scene.physics.cfl * static_cast<double>(sp.h) / static_cast<double>(sp.c0);
    if (dt_next >= options.dt_collapse * acoustic) return;
    std::ostringstream o;
    o << "step " << info.step << ", t = " << info.time << " s: the time step collapsed to " << dt_next
      << " s (below " << options.dt_collapse << " of the acoustic step " << acoustic << " s; max |v| = " << info.max_speed
      << " m/s): the accelerations blew up. The run stopped; the last good state is at t = " << last_good_time
      << " s.";
    throw SimulationError(o.str());
}

void Simulation::Impl::device_failed(const DeviceError& e, double dt) {
    // A device failed mid-step: the device state is lost, the last good state is on the host.
    std::ostringstream o;
    o << "step " << info.step + 1 << ", t = " << info.time + dt << " s: " << e.what()
      << ". The run stopped; the last good state is at t = " << last_good_time << " s.";
    throw DeviceError(e.code(), o.str(), e.call(), e.device());
}

BalanceMode balance_mode_from_name(const std::string& name) {
    if (name == "dynamic") return BalanceMode::dynamic;
    if (name == "static") return BalanceMode::fixed;
    if (name == "off") return BalanceMode::off;
    throw Error("unknown balance mode '" + name + "' (use dynamic, static or off)");
}

Simulation::Simulation(const Scene& scene, const Options& options) : impl_(std::make_unique<Impl>(scene, options)) {
    if (options.setup_on_device && scene::LatticePlan::supports(scene)) {
        if (options.on_setup) options.on_setup("planning the particles of the scene");
        impl_->plan = scene::LatticePlan::make(scene);
        impl_->init(Particles(), nullptr, &*impl_->plan);
    } else {
        if (options.on_setup) options.on_setup("building the particles of the scene on the host");
        impl_->init(scene.build_particles(), nullptr);
    }
}

Simulation::Simulation(const Scene& scene, const Particles& p, const Options& options)
    : impl_(std::make_unique<Impl>(scene, options)) {
    impl_->init(p, nullptr);
}

namespace {
// A checkpoint's particles as the host holds them (the census and the split read positions).
Particles particles_of(const Checkpoint& c, const device::Grid& grid) {
    return device::decode_particles(grid, c.pos.data(), c.velrho.data(), c.id.data(), c.size());
}
}  // namespace

Simulation::Simulation(const Scene& scene, const Checkpoint& c, const Options& options)
    : impl_(std::make_unique<Impl>(scene, options)) {
    if (c.scene_hash != scene_hash(scene))
        throw CheckpointError("(in memory)", "written for another scene (its scene hash differs)");
    impl_->init(particles_of(c, impl_->grid), &c);
}

void Simulation::Impl::init(const Particles& p, const Checkpoint* c, const scene::LatticePlan* lattice) {
    auto& m = *this;
    cl_rt::OpenOptions open{options.profile, options.seams ? options.seams->faults : std::vector<testing::Fault>{}};
    if (options.seams) open.max_allocation = options.seams->max_allocation;
    std::string spec = options.devices.empty() ? default_device_spec() : options.devices;
    if (options.ranks) {
        // This rank's devices (dealt from the node's, or its own clause of a per-rank spec). The
        // memory plan is one process's: across ranks a device that runs short says so when it
        // allocates.
        std::string mine;
        for (auto i : multi::rank_devices(list_devices(), spec, options.ranks->place()))
            mine += (mine.empty() ? "" : ",") + std::to_string(i);
        spec = mine;
    } else {
        // The memory plan before any context or buffer: a scene that cannot fit stops here, and a
        // device whose slab would hold a buffer above its largest allocation is opened as several slabs.
        const auto infos = cl_rt::selected_infos(spec, open);
        const MemoryPlan plan = lattice ? detail::plan_memory(scene, detail::census_of(scene, *lattice), infos, options)
                                        : plan_memory(scene, p, infos, options);
        check_fits(plan);
        open.slabs = plan.slabs_per_device();
    }
    m.devices = cl_rt::open_devices(spec, open);
    std::vector<cl_rt::Device*> devs;
    for (auto& d : m.devices) {
        d->profiler().enable(options.profile);
        d->profiler().trace(options.profile && options.trace);
        devs.push_back(d.get());
    }
    multi::DriverOptions dopt;
    dopt.interaction = options.interaction != Interaction::automatic ? options.interaction : scene.run.interaction;
    dopt.balance = options.balance == BalanceMode::dynamic ? balance::Mode::dynamic
                   : options.balance == BalanceMode::fixed ? balance::Mode::static_
                                                           : balance::Mode::off;
    dopt.balance_log = options.balance_log;
    dopt.headroom = options.capacity_headroom;
    dopt.cell_headroom = options.cell_headroom;
    using Mode = cl_rt::EventSet::Mode;
    dopt.wait = options.wait == WaitMode::poll    ? Mode::poll
                : options.wait == WaitMode::block ? Mode::block
                                                  : Mode::callbacks;
    if (options.seams) dopt.seams = *options.seams;
    dopt.progress = options.on_setup;
    dopt.ranks = options.ranks;
    // A checkpoint's cuts, which the driver takes when they fit its slab count (every rank's slabs).
    if (c) dopt.cuts.assign(c->cuts.begin(), c->cuts.end());
    // An OpenCL call that throws outside the runtime's wrappers is a DeviceError too.
    const auto k = cl_rt::guarded("setting up the devices", "", [&] {
        m.driver = lattice ? std::make_unique<multi::SlabDriver>(devs, m.grid, m.scene, *lattice, dopt)
                        : std::make_unique<multi::SlabDriver>(devs, m.grid, m.scene, p, dopt);
        return m.driver->start();  // dt = 0: the checks, reductions and a_0 into accel
    });
    if (k.kick.bad_index >= 0) m.fail(k);
    m.info.removed = k.removed;
    m.info.particles = m.driver->owned();
    m.info.fluid = k.kick.fluid;
    m.info.kinetic_energy = k.kick.kinetic_energy;
    m.info.max_speed = std::sqrt(k.kick.max_speed2);
    m.info.cells = m.driver->slabs().size() == 1 ? m.driver->slabs()[0].cells->cells() : 0;
    m.dt_next = m.next_dt(k.kick);
    m.last_good = p;  // empty with a plan: the host never held the particles
    if (lattice) m.fluid_total = static_cast<std::size_t>(lattice->fluid_count);
    for (std::size_t i = 0; i < p.size(); ++i) m.fluid_total += p.type[i] == ParticleType::fluid;
    if (c) m.restore(*c);
    m.setup_ahead();
}

void Simulation::Impl::restore(const Checkpoint& c) {
    // The first pass sorted the decoded particles; the checkpoint's arrays go over the owned ones.
    // Written on this device count with the same split, each slab holds its block of the file in
    // its order: the arrays go in as they are. Otherwise by id (the order is the new split's).
    // Across ranks each rank restores its own slabs (its block of the file starts after the blocks
    // of the slabs before it, whichever rank holds them).
    auto& slabs = driver->slabs();
    bool same = c.counts.size() == slabs.size();
    for (std::size_t d = 0; same && d < slabs.size(); ++d)
        same = !driver->here(d) || slabs[d].store->ranges.owned == c.counts[d];
    std::unordered_map<std::uint32_t, std::size_t> index;
    if (!same)
        for (std::size_t i = 0; i < c.size(); ++i) index[c.id[i]] = i;
    std::size_t from = 0;
    cl_rt::guarded("restoring the checkpoint", "", [&] {
        for (std::size_t slab = 0; slab < slabs.size(); ++slab) {
            if (!driver->here(slab)) {
                if (same) from += c.counts[slab];
                continue;
            }
            auto& s = slabs[slab];
            auto& d = *s.device;
            auto& st = *s.store;
            const std::size_t n = st.ranges.owned, first = st.ranges.first_owned();
            if (n == 0) continue;
            std::vector<float> pos(4 * n), velrho(4 * n), accel(4 * n);
            if (same) {
                std::copy_n(c.pos.begin() + 4 * from, 4 * n, pos.begin());
                std::copy_n(c.velrho.begin() + 4 * from, 4 * n, velrho.begin());
                std::copy_n(c.accel.begin() + 4 * from, 4 * n, accel.begin());
                // The ids go with them: a particle on a cell face may have sorted elsewhere in the
                // first pass (its position decoded and encoded again), while the file's block is
                // the slab's sorted order as saved. The cell tables follow at the next exchange,
                // before any force pass.
                d.write(st.id, c.id.data() + from, n, first);
                from += n;
            } else {
                std::vector<std::uint32_t> ids(n);
                d.read(st.id, ids.data(), n, first);
                for (std::size_t i = 0; i < n; ++i) {
                    const auto it = index.find(ids[i]);
                    if (it == index.end()) throw Error("restoring a checkpoint: a particle id not in it");
                    const std::size_t j = it->second;
                    // The position as this device's first pass encoded it (the key decides the
                    // order the slab sorted); velocity, density and the last forces as saved.
                    std::copy_n(c.velrho.begin() + 4 * j, 4, velrho.begin() + 4 * i);
                    std::copy_n(c.accel.begin() + 4 * j, 4, accel.begin() + 4 * i);
                }
                d.read(st.pos, pos.data(), 4 * n, 4 * first);
            }
            d.write(st.pos, pos.data(), 4 * n, 4 * first);
            d.write(st.velrho, velrho.data(), 4 * n, 4 * first);
            d.write(st.accel, accel.data(), 4 * n, 4 * first);
            d.finish();
        }
        return 0;
    });
    info.step = c.step;
    info.time = c.time;
    info.dt = c.dt;
    info.removed = c.removed;
    info.particles = driver->owned();
    info.fluid = c.fluid;
    info.kinetic_energy = c.kinetic_energy;
    info.max_speed = c.max_speed;
    info.cells = c.cells;
    dt_next = c.dt_next;
    last_good_time = c.time;
}

namespace {
// Room for the next slab's n particles at the end of c's arrays (its count recorded); returns
// where they start.
std::size_t grow_for_slab(Checkpoint& c, std::size_t n) {
    const std::size_t at = c.size();
    c.counts.push_back(n);
    c.pos.resize(4 * (at + n));
    c.velrho.resize(4 * (at + n));
    c.accel.resize(4 * (at + n));
    c.id.resize(at + n);
    return at;
}
}  // namespace

Checkpoint Simulation::checkpoint() {
    auto& m = *impl_;
    if (!m.in_flight.empty())
        throw Error("checkpoint(): steps run ahead of the host; save after run_until returns, not in the step callback");
    m.drop_left();
    Checkpoint c;
    c.clsph_version = version();
    c.scene_hash = scene_hash(m.scene);
    c.step = m.info.step;
    c.time = m.info.time;
    c.dt = m.info.dt;
    c.dt_next = m.dt_next;
    c.removed = m.info.removed;
    c.fluid = m.info.fluid;
    c.cells = m.info.cells;
    c.kinetic_energy = m.info.kinetic_energy;
    c.max_speed = m.info.max_speed;
    for (auto cut : m.driver->cuts()) c.cuts.push_back(cut);
    if (m.driver->across_ranks()) {
        m.checkpoint_across_ranks(c);
        return c;
    }
    cl_rt::guarded("reading the checkpoint", "", [&] {
        for (auto& s : m.driver->slabs()) {
            auto& d = *s.device;
            auto& st = *s.store;
            const std::size_t n = st.ranges.owned, first = st.ranges.first_owned(), at = grow_for_slab(c, n);
            if (n == 0) continue;
            d.read(st.pos, c.pos.data() + 4 * at, 4 * n, 4 * first);
            d.read(st.velrho, c.velrho.data() + 4 * at, 4 * n, 4 * first);
            d.read(st.accel, c.accel.data() + 4 * at, 4 * n, 4 * first);
            d.read(st.id, c.id.data() + at, n, first);
        }
        return 0;
    });
    return c;
}

void Simulation::save(const std::string& path) {
    // Across ranks every rank takes part in checkpoint(); rank 0 writes the file.
    const Checkpoint c = checkpoint();
    if (!impl_->options.ranks || impl_->options.ranks->rank() == 0) write_checkpoint(path, c);
}

void Simulation::Impl::checkpoint_across_ranks(Checkpoint& c) {
    // Each rank's slabs as bytes (slab, count, then the four arrays), gathered on every rank and
    // laid out in slab order: the file one process on as many devices would write.
    std::string mine;
    auto put = [&](const void* p, std::size_t bytes) { mine.append(static_cast<const char*>(p), bytes); };
    auto& slabs = driver->slabs();
    cl_rt::guarded("reading the checkpoint", "", [&] {
        for (std::size_t d = 0; d < slabs.size(); ++d) {
            if (!driver->here(d)) continue;
            auto& s = slabs[d];
            auto& st = *s.store;
            const std::uint64_t n = st.ranges.owned, first = st.ranges.first_owned(), slab = d;
            std::vector<float> pos(4 * n), velrho(4 * n), accel(4 * n);
            std::vector<std::uint32_t> id(n);
            if (n) {
                s.device->read(st.pos, pos.data(), 4 * n, 4 * first);
                s.device->read(st.velrho, velrho.data(), 4 * n, 4 * first);
                s.device->read(st.accel, accel.data(), 4 * n, 4 * first);
                s.device->read(st.id, id.data(), n, first);
            }
            put(&slab, 8);
            put(&n, 8);
            put(pos.data(), 16 * n);
            put(velrho.data(), 16 * n);
            put(accel.data(), 16 * n);
            put(id.data(), 4 * n);
        }
        return 0;
    });
    struct Part { const char* at; std::uint64_t n; };
    std::vector<Part> parts(slabs.size(), Part{nullptr, 0});
    const auto all = options.ranks->gather_text(mine);
    for (const auto& r : all)
        for (std::size_t k = 0; k + 16 <= r.size();) {
            std::uint64_t slab = 0, n = 0;
            std::memcpy(&slab, r.data() + k, 8);
            std::memcpy(&n, r.data() + k + 8, 8);
            if (slab >= parts.size() || r.size() - k - 16 < 52 * n) throw Error("checkpoint across ranks: a rank's part is malformed");
            parts[slab] = {r.data() + k + 16, n};
            k += 16 + 52 * n;
        }
    for (const auto& part : parts) {
        const std::size_t n = part.n, at = grow_for_slab(c, n);
        if (n == 0) continue;
        std::memcpy(c.pos.data() + 4 * at, part.at, 16 * n);
        std::memcpy(c.velrho.data() + 4 * at, part.at + 16 * n, 16 * n);
        std::memcpy(c.accel.data() + 4 * at, part.at + 32 * n, 16 * n);
        std::memcpy(c.id.data() + at, part.at + 48 * n, 4 * n);
    }
}

Simulation::~Simulation() = default;

const StepInfo& Simulation::step() {
    auto& m = *impl_;
    if (m.ahead) {
        m.run_ahead(std::numeric_limits<double>::infinity(), {}, 1);
        return m.info;
    }
    const double dt = m.dt_next;
    multi::StepOutcome k;
    try {
        k = cl_rt::guarded("taking a step", "", [&] { return m.driver->step(dt); });
    } catch (const DeviceError& e) {
        m.device_failed(e, dt);
    }
    if (k.kick.bad_index >= 0) m.fail(k);
    m.info.step += 1;
    m.info.time += dt;
    m.info.dt = dt;
    m.info.removed += k.removed;
    m.info.particles = m.driver->owned();
    m.info.fluid = k.kick.fluid;
    m.info.kinetic_energy = k.kick.kinetic_energy;
    m.info.max_speed = std::sqrt(k.kick.max_speed2);
    m.info.cells = m.driver->slabs().size() == 1 ? m.driver->slabs()[0].cells->cells() : 0;
    m.info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m.started).count();
    m.dt_next = m.next_dt(k.kick);
    m.check_dt_collapse();
    return m.info;
}

void Simulation::run_until(double t, const std::function<void(const StepInfo&)>& on_step) {
    if (impl_->ahead) {
        impl_->run_ahead(t, on_step, 0);
        return;
    }
    while (impl_->info.time < t - 1e-12) {
        // Land on t exactly rather than overshooting it by most of a step.
        impl_->dt_next = std::min(impl_->dt_next, std::max(t - impl_->info.time, 1e-12));
        const auto& s = step();
        if (on_step) on_step(s);
    }
}

namespace {

// The devices keep density only; pressure follows from it by the equation of state (Tait, gamma 7).
void fill_pressure(Particles& p, const SphParams& sp) {
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.density[i] / sp.rho0;
        p.pressure[i] = static_cast<float>(sp.eos_b * (std::pow(x, 7.0) - 1.0));
    }
}

}  // namespace

Particles Simulation::particles() {
    auto& m = *impl_;
    Particles p = cl_rt::guarded("downloading the particles", "", [&] { return m.driver->download(); });
    fill_pressure(p, m.driver->params());
    m.last_good = p;
    m.last_good_time = m.info.time;
    return p;
}

std::vector<Particles> Simulation::particles_by_device(const Selection& which) {
    auto& m = *impl_;
    auto& slabs = m.driver->slabs();
    // Across ranks: this rank's slabs (the others' pieces are theirs to write).
    std::vector<std::size_t> here;
    for (std::size_t d = 0; d < slabs.size(); ++d)
        if (m.driver->here(d)) here.push_back(d);
    std::vector<Particles> pieces(slabs.size());
    auto download = [&](std::size_t k) {
        pieces[k] = cl_rt::guarded("downloading the particles", slabs[k].device->label(), [&] {
            return which.all() ? slabs[k].store->download() : m.driver->download_every(k, which.stride, which.box);
        });
        fill_pressure(pieces[k], m.driver->params());
    };
    if (here.size() == 1) {
        download(here[0]);
    } else {
        // Each device's read waits on its own queue: one thread per device, so they overlap.
        std::vector<std::exception_ptr> errors(slabs.size());
        std::vector<std::thread> threads;
        for (std::size_t k : here)
            threads.emplace_back([&, k] {
                try {
                    download(k);
                } catch (...) {
                    errors[k] = std::current_exception();
                }
            });
        for (auto& t : threads) t.join();
        for (const auto& e : errors)
            if (e) std::rethrow_exception(e);
    }
    if (m.driver->across_ranks()) {
        std::vector<Particles> mine;
        for (auto k : here) mine.push_back(std::move(pieces[k]));
        return mine;  // (a rank's part is no state to go back to)
    }
    if (!which.all()) return pieces;  // a thinned state is no state to go back to
    Particles all;
    for (const auto& p : pieces)
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    m.last_good = std::move(all);
    m.last_good_time = m.info.time;
    return pieces;
}

Particles Simulation::particles(const Selection& which) {
    if (which.all()) return particles();
    Particles all;
    for (const auto& p : particles_by_device(which))
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    return all;
}

bool Simulation::steps_ahead() const { return impl_->ahead; }

const Particles& Simulation::last_good() const {
    // Set up on the devices and nothing downloaded yet: the last good state is the scene's start,
    // built on the host only now that it is asked for.
    if (impl_->last_good.size() == 0 && impl_->plan) impl_->last_good = impl_->plan->particles();
    return impl_->last_good;
}
const StepInfo& Simulation::info() const { return impl_->info; }
double Simulation::time() const { return impl_->info.time; }
const Scene& Simulation::scene() const { return impl_->scene; }

std::vector<std::string> Simulation::device_names() const {
    std::vector<std::string> names;
    for (const auto& d : impl_->devices) names.push_back(d->label());
    return names;
}

std::vector<DeviceShare> Simulation::shares() const {
    std::vector<DeviceShare> out;
    auto& slabs = impl_->driver->slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!impl_->driver->here(d)) continue;  // across ranks: this rank's
        auto& s = slabs[d];
        out.push_back({s.device->label(), s.store->ranges.owned, s.first_col, s.end_col, s.force_seconds,
                       s.store->ranges.ghosts_before + s.store->ranges.ghosts_after, s.received_bytes,
                       s.calibration.fixed + s.calibration.per_unit * s.calibration.work_total, s.calibration.fixed,
                       s.physics->interaction()});
    }
    return out;
}

TriangleMesh Simulation::surface(const SurfaceOptions& options) {
    auto& m = *impl_;
    m.one_process("free surfaces");
    return cl_rt::guarded("extracting the free surface", "",
                          [&] { return surface::extract_surface(*m.driver, m.grid, m.scene, options); });
}

Simulation::Impl::ProbePoints Simulation::Impl::probe_points() const { return probes::sample_points(scene); }

Image Simulation::render(const TriangleMesh& surface, const CameraView& camera) {
    auto& m = *impl_;
    m.one_process("images");
    return cl_rt::guarded("rendering an image", "", [&] { return render::render_scene(*m.driver, m.grid, m.scene, surface, camera); });
}

std::vector<ProbeSample> Simulation::sample_probes() {
    auto& m = *impl_;
    const auto pp = m.probe_points();
    const auto& points = pp.points;
    std::vector<probes::Sums> sums;
    if (m.ahead && m.probed_step == m.info.step && m.probed.size() == points.size()) {
        sums = m.probed;  // computed in the queue after this probe step (the step ahead)
    } else {
        if (!m.in_flight.empty())
            throw Error("sample_probes(): steps run ahead of the host (Options::steps_ahead), so inside the step "
                        "callback the probes are available only on probe steps (run.probe_every)");
        sums = cl_rt::guarded("sampling the probes", "", [&] { return m.driver->probe(points); });
    }
    // What each probe measures: probes/gauges.hpp (the same for sums from the step ahead).
    const auto values = probes::values(m.scene, pp, sums);
    std::vector<ProbeSample> out;
    for (std::size_t i = 0; i < m.scene.probes.size(); ++i) out.push_back({m.scene.probes[i].name, m.info.time, values[i]});
    return out;
}

std::vector<KernelTime> Simulation::profile() {
    std::vector<KernelTime> out;
    for (auto& d : impl_->devices)
        for (const auto& [name, st] : d->profiler().stats()) out.push_back({name, d->label(), st.calls, st.seconds});
    return out;
}

std::vector<CommandSpan> Simulation::take_trace() {
    std::vector<CommandSpan> out;
    for (auto& d : impl_->devices)
        for (auto& t : d->profiler().take_trace()) out.push_back({d->label(), std::move(t.name), t.start, t.end});
    return out;
}

std::vector<KernelTime> Simulation::host_phases() const {
    std::vector<KernelTime> out;
    for (const auto& [name, seconds] : impl_->driver->phase_seconds()) out.push_back({name, {}, impl_->info.step, seconds});
    return out;
}

std::vector<MemoryReport> Simulation::memory() const {
    std::vector<MemoryReport> out;
    auto& slabs = impl_->driver->slabs();
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!impl_->driver->here(d)) continue;  // across ranks: this rank's
        auto& s = slabs[d];
        MemoryReport r;
        r.device = s.device->label();
        r.particles = s.store->ranges.owned;
        r.peak_bytes = s.device->memory().counters().peak;
        r.capacity_particles = s.store->capacity();
        r.peak_buffers = s.device->memory().at_peak();
        out.push_back(r);
    }
    return out;
}

}  // namespace clsph
