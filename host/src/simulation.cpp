// The facade behind clsph::Simulation: scene -> particles -> device pipeline -> steps.
#include "clsph/simulation.hpp"

#include "cl/device.hpp"
#include "clsph/error.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace clsph {

struct Simulation::Impl {
    Scene scene;
    Options options;
    std::vector<std::unique_ptr<cl_rt::Device>> devices;
    device::Grid grid;
    std::unique_ptr<device::ParticleStore> store;
    std::unique_ptr<device::CellPipeline> cells;
    std::unique_ptr<device::Physics> physics;
    StepInfo info;
    double dt_next = 0.0;
    Particles last_good;
    std::size_t fluid_total = 0;
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

    Impl(const Scene& s, const Options& o)
        : scene(s),
          options(o),
          grid(device::Box{s.domain.min, s.domain.max}, s.physics.support(), s.domain.split_axis, s.domain.periodic) {}

    cl_rt::Device& dev() { return *devices.front(); }

    double next_dt(const device::KickResult& k) const {
        if (scene.run.fixed_dt > 0) return scene.run.fixed_dt;
        const auto& sp = physics->params();
        const double h = sp.h;
        const double amax = std::sqrt(k.max_accel2), vmax = std::sqrt(k.max_speed2);
        // Monaghan's force and acoustic (CFL) limits: dt = cfl min(sqrt(h/|a|max), h/(c0 + |v|max)).
        const double dt_force = amax > 0 ? std::sqrt(h / amax) : std::numeric_limits<double>::infinity();
        const double dt_sound = h / (sp.c0 + vmax);
        return scene.physics.cfl * std::min(dt_force, dt_sound);
    }

    [[noreturn]] void fail(std::int64_t index) {
        auto& d = dev();
        cl_uint id = 0;
        float vr[4] = {0, 0, 0, 0};
        d.read(store->id, &id, 1, static_cast<std::size_t>(index));
        d.read(store->velrho, vr, 4, 4 * static_cast<std::size_t>(index));
        std::ostringstream o;
        const bool fluid = (id >> CLSPH_TYPE_SHIFT) == CLSPH_TYPE_FLUID;
        o << "step " << info.step + 1 << ", t = " << info.time + dt_next << " s: particle " << (id & CLSPH_ID_MASK)
          << " (" << (fluid ? "fluid" : "boundary") << ") ";
        if (!std::isfinite(vr[0]) || !std::isfinite(vr[1]) || !std::isfinite(vr[2]) || !std::isfinite(vr[3]))
            o << "has a non-finite velocity or density";
        else
            o << "has density " << vr[3] << " kg/m^3, outside the allowed band [" << physics->params().rho_min << ", "
              << physics->params().rho_max << "]";
        o << " (time step " << dt_next << " s). The run stopped; the last good state is at t = "
          << last_good_time << " s.";
        throw SimulationError(o.str());
    }

    double last_good_time = 0.0;
};

Simulation::Simulation(const Scene& scene, const Options& options) : impl_(std::make_unique<Impl>(scene, options)) {
    auto& m = *impl_;
    const Particles p = scene.build_particles();
    m.devices = cl_rt::open_devices(options.devices.empty() ? default_device_spec() : options.devices,
                                    cl_rt::OpenOptions{options.profile});
    auto& d = m.dev();
    d.profiler().enable(options.profile);
    m.store = std::make_unique<device::ParticleStore>(d, m.grid, p.size(), options.capacity_headroom);
    m.store->upload(p);
    m.cells = std::make_unique<device::CellPipeline>(d, m.grid);
    m.physics = std::make_unique<device::Physics>(d, m.grid, m.scene, options.coarse);
    const auto pass = m.cells->run(*m.store);
    m.info.removed = pass.removed;
    m.physics->forces(*m.store, *m.cells, m.store->scratch);
    const auto k = m.physics->kick(*m.store, 0.0);  // dt = 0: the checks, reductions and a_0 into accel
    if (k.bad_index >= 0) m.fail(k.bad_index);
    m.info.particles = m.store->ranges.owned;
    m.info.fluid = k.fluid;
    m.info.kinetic_energy = k.kinetic_energy;
    m.info.max_speed = std::sqrt(k.max_speed2);
    m.dt_next = m.next_dt(k);
    m.last_good = p;
    for (std::size_t i = 0; i < p.size(); ++i) m.fluid_total += p.type[i] == ParticleType::fluid;
}

Simulation::~Simulation() = default;

const StepInfo& Simulation::step() {
    auto& m = *impl_;
    const double dt = m.dt_next;
    m.physics->kick_drift(*m.store, dt);
    const auto pass = m.cells->run(*m.store);
    m.physics->forces(*m.store, *m.cells, m.store->scratch);
    const auto k = m.physics->kick(*m.store, dt);
    if (k.bad_index >= 0) m.fail(k.bad_index);
    m.info.step += 1;
    m.info.time += dt;
    m.info.dt = dt;
    m.info.removed += pass.removed;
    m.info.particles = m.store->ranges.owned;
    m.info.fluid = k.fluid;
    m.info.kinetic_energy = k.kinetic_energy;
    m.info.max_speed = std::sqrt(k.max_speed2);
    m.info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m.started).count();
    m.dt_next = m.next_dt(k);
    return m.info;
}

void Simulation::run_until(double t, const std::function<void(const StepInfo&)>& on_step) {
    while (impl_->info.time < t - 1e-12) {
        // Land on t exactly rather than overshooting it by most of a step.
        impl_->dt_next = std::min(impl_->dt_next, std::max(t - impl_->info.time, 1e-12));
        const auto& s = step();
        if (on_step) on_step(s);
    }
}

Particles Simulation::particles() {
    auto& m = *impl_;
    Particles p = m.store->download();
    const auto& sp = m.physics->params();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.density[i] / sp.rho0;
        p.pressure[i] = static_cast<float>(sp.eos_b * (std::pow(x, 7.0) - 1.0));
    }
    m.last_good = p;
    m.last_good_time = m.info.time;
    return p;
}

const Particles& Simulation::last_good() const { return impl_->last_good; }
const StepInfo& Simulation::info() const { return impl_->info; }
double Simulation::time() const { return impl_->info.time; }
const Scene& Simulation::scene() const { return impl_->scene; }

std::vector<std::string> Simulation::device_names() const {
    std::vector<std::string> names;
    for (const auto& d : impl_->devices) names.push_back(d->label());
    return names;
}

std::vector<ProbeSample> Simulation::sample_probes() {
    auto& m = *impl_;
    std::vector<std::array<double, 3>> points;
    std::vector<std::size_t> first;  // first point of each probe
    const double dz = 0.5 * m.scene.physics.dp;
    const double z0 = m.scene.domain.min[2], z1 = m.scene.domain.max[2];
    for (const auto& pr : m.scene.probes) {
        first.push_back(points.size());
        if (pr.kind == Probe::Kind::pressure) {
            points.push_back(pr.point);
        } else {
            for (double z = z0; z <= z1 + 1e-12; z += dz) points.push_back({pr.point[0], pr.point[1], z});
        }
    }
    first.push_back(points.size());
    const auto sums = m.physics->probe(*m.store, *m.cells, points);
    std::vector<ProbeSample> out;
    for (std::size_t i = 0; i < m.scene.probes.size(); ++i) {
        const auto& pr = m.scene.probes[i];
        ProbeSample s{pr.name, m.info.time, std::numeric_limits<double>::quiet_NaN()};
        if (pr.kind == Probe::Kind::pressure) {
            const auto& v = sums[first[i]];
            // Shepard-normalised; a point with too little fluid around it reads as no value.
            if (v[0] > 0.1f) s.value = v[1] / v[0];
        } else {
            // Highest z where the fluid fraction sum V W crosses 1/2, interpolated linearly.
            for (std::size_t k = first[i + 1] - 1; k > first[i]; --k) {
                const double f_hi = sums[k][0], f_lo = sums[k - 1][0];
                if (f_lo >= 0.5 && f_hi < 0.5) {
                    const double zlo = points[k - 1][2];
                    s.value = zlo + dz * (f_lo - 0.5) / (f_lo - f_hi);
                    break;
                }
            }
        }
        out.push_back(s);
    }
    return out;
}

std::vector<KernelTime> Simulation::profile() {
    std::vector<KernelTime> out;
    for (auto& d : impl_->devices)
        for (const auto& [name, st] : d->profiler().stats()) out.push_back({name, st.calls, st.seconds});
    return out;
}

std::vector<MemoryReport> Simulation::memory() const {
    std::vector<MemoryReport> out;
    for (const auto& d : impl_->devices) {
        MemoryReport r;
        r.device = d->label();
        r.particles = impl_->store->ranges.owned;
        r.peak_bytes = d->memory().counters().peak;
        r.capacity_particles = impl_->store->capacity();
        out.push_back(r);
    }
    return out;
}

}  // namespace clsph
