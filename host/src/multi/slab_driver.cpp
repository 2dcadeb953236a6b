#include "multi/slab_driver.hpp"

#include "clsph/error.hpp"
#include "multi/link.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace clsph::multi {
namespace {
// Adds the wall time of a scope to one phase's total.
class PhaseTimer {
public:
    PhaseTimer(std::map<std::string, double>& phases, const char* name)
        : phases_(phases), name_(name), start_(std::chrono::steady_clock::now()) {}
    ~PhaseTimer() { phases_[name_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    PhaseTimer(const PhaseTimer&) = delete;
    PhaseTimer& operator=(const PhaseTimer&) = delete;

private:
    std::map<std::string, double>& phases_;
    const char* name_;
    std::chrono::steady_clock::time_point start_;
};

balance::Mode mode_of(const std::string& m) {
    if (auto mode = balance::mode_from_string(m)) return *mode;
    throw Error("--balance: unknown mode '" + m + "' (use dynamic, static or off)");
}
}  // namespace

SlabDriver::SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
                       const Particles& p, const DriverOptions& options)
    : grid_(grid), options_(options) {
    const std::size_t D = devices.size(), columns = grid.params().n_s;
    balance::Options bo;
    bo.mode = mode_of(options.balance);
    // Every device keeps at least one column: an idle device is never measured again, so one noisy
    // step could idle it for good (balance/options.hpp).
    bo.allow_idle = false;
    balancer_ = std::make_unique<balance::Balancer>(D, columns, bo);

    // Where each particle is: its key (and column) on the host, for the first cut and the upload.
    std::vector<std::uint32_t> key(p.size());
    balance::ColumnProfile profile;
    profile.work.assign(columns, 0.0);
    profile.particles.assign(columns, 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        std::array<float, 3> off{};
        key[i] = grid.locate(p.position[i], off);
        if (key[i] == grid.params().invalid_key) continue;
        const std::size_t c = grid.cell_of_key(key[i])[0];
        profile.work[c] += p.type[i] == ParticleType::fluid ? 1.0 : balance::default_boundary_weight;
        profile.particles[c] += 1;
    }
    boundary_per_column_.assign(columns, 0);
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.type[i] == ParticleType::boundary && key[i] != grid.params().invalid_key)
            boundary_per_column_[grid.cell_of_key(key[i])[0]] += 1;
    const auto cuts = D == 1 ? std::vector<std::size_t>{0, columns} : balancer_->initial_cuts(profile);
    slabs_.resize(D);
    for (std::size_t d = 0; d < D; ++d) {
        Slab& s = slabs_[d];
        s.device = devices[d];
        s.first_col = cuts[d];
        s.end_col = cuts[d + 1];
        Particles mine;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const bool outside = key[i] == grid.params().invalid_key;
            const std::size_t c = outside ? 0 : grid.cell_of_key(key[i])[0];
            // Particles outside the domain go to the first device, whose first pass removes them.
            if ((outside && d == 0) || (!outside && c >= s.first_col && c < s.end_col))
                mine.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
        }
        const std::size_t capacity = D == 1 ? mine.size() : std::max<std::size_t>(
            static_cast<std::size_t>(static_cast<double>(p.size()) / static_cast<double>(D) * (1.0 + options.headroom)),
            mine.size());
        s.store = std::make_unique<device::ParticleStore>(*s.device, grid, capacity, options.headroom);
        s.store->upload(mine);
        s.cells = std::make_unique<device::CellPipeline>(*s.device, grid);
        s.physics = std::make_unique<device::Physics>(*s.device, grid, scene, options.coarse);
        if (D > 1) s.device->profiler().enable(true);  // the balancer needs each force pass's time
    }
    if (!options.balance_log.empty()) {
        log_file_ = std::make_unique<std::ofstream>(options.balance_log);
        if (!*log_file_) throw Error("--balance-log: cannot write " + options.balance_log);
        log_ = std::make_unique<balance::BalanceLog>(*log_file_, D);
    }
}

std::uint32_t SlabDriver::column_key(std::size_t column) const {
    const auto& g = grid_.params();
    if (column >= g.n_s) return g.invalid_key;
    if (g.shift_s >= 32) return 0;
    return static_cast<std::uint32_t>(column) << g.shift_s;
}

std::size_t SlabDriver::owner_of(std::uint32_t key) const {
    const std::size_t c = grid_.cell_of_key(key)[0];
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (c >= slabs_[d].first_col && c < slabs_[d].end_col) return d;
    return slabs_.size() - 1;
}

std::vector<std::size_t> SlabDriver::cuts() const {
    std::vector<std::size_t> c;
    for (const auto& s : slabs_) c.push_back(s.first_col);
    c.push_back(slabs_.back().end_col);
    return c;
}

std::size_t SlabDriver::owned() const {
    std::size_t n = 0;
    for (const auto& s : slabs_) n += s.store->ranges.owned;
    return n;
}

std::size_t SlabDriver::redistribute() {
    const std::size_t D = slabs_.size();
    const std::uint32_t invalid = grid_.params().invalid_key;
    std::size_t removed = 0;
    moved_ = 0;
    if (D == 1) {
        Slab& s = slabs_[0];
        auto& ps = *s.store;
        const auto at = s.cells->sort_particles(ps, ps.ranges.active(), ps.ranges.first_owned(), ps.ranges.end_owned(),
                                                {invalid});
        removed = ps.ranges.owned - at[0];
        ps.ranges = device::ParticleRanges{0, at[0], 0};
        s.cells->build_tables(ps, at[0]);
        return removed;
    }
    // 1. Sort each device's owned particles (stale ghosts dropped); find leavers and edge columns.
    //    All sorts are enqueued before any result is waited for, so the devices sort together.
    struct Edges { std::size_t a0 = 0, a1 = 0, nv = 0, h0 = 0, h1 = 0; ParticleBatch leavers, first_col, last_col; };
    std::vector<Edges> e(D);
    {
        PhaseTimer t(phases_, "exchange: sort");
        for (std::size_t d = 0; d < D; ++d) {
            auto& ps = *slabs_[d].store;
            slabs_[d].cells->enqueue_sort(ps, ps.ranges.active(), ps.ranges.first_owned(), ps.ranges.end_owned());
        }
    }
    {
        PhaseTimer t(phases_, "exchange: read leavers and edges");
        for (std::size_t d = 0; d < D; ++d) {
            Slab& s = slabs_[d];
            auto& ps = *s.store;
            const std::size_t owned = ps.ranges.owned;
            const auto at = s.cells->locate(
                ps, ps.ranges.active(),
                {column_key(s.first_col), column_key(s.end_col), invalid, column_key(std::min(s.first_col + 1, s.end_col)),
                 column_key(s.end_col > s.first_col ? s.end_col - 1 : s.end_col)});
            Edges& x = e[d];
            x.a0 = at[0];
            x.a1 = std::max(at[1], x.a0);
            x.nv = at[2];
            x.h0 = std::min(std::max(at[3], x.a0), x.a1);
            x.h1 = std::min(std::max(at[4], x.a0), x.a1);
            removed += owned - x.nv;
            ParticleBatch back;
            read_range(ps, 0, x.a0, x.leavers);
            read_range(ps, x.a1, x.nv - x.a1, back);
            x.leavers.append(back, 0, back.size());
            // Edge columns only where a neighbour will read them as ghosts.
            bool left = false, right = false;
            for (std::size_t l = 0; l < d; ++l) left = left || !slabs_[l].empty();
            for (std::size_t r = d + 1; r < D; ++r) right = right || !slabs_[r].empty();
            if (!s.empty() && left) read_range(ps, x.a0, x.h0 - x.a0, x.first_col);
            if (!s.empty() && right) read_range(ps, x.h1, x.a1 - x.h1, x.last_col);
        }
    }
    // 2. Route every leaver to the device owning its column now.
    std::vector<ParticleBatch> arrivals(D);
    std::vector<ParticleBatch> incoming(D);
    {
        PhaseTimer t(phases_, "exchange: route on the host");
        for (std::size_t d = 0; d < D; ++d)
            for (std::size_t i = 0; i < e[d].leavers.size(); ++i) {
                arrivals[owner_of(e[d].leavers.key(i))].append(e[d].leavers, i, 1);
                ++moved_;
            }
        // 3. Each device's ghosts: the last column of the nearest non-empty device before it and the
        //    first column of the nearest one after it, arrivals in those columns included.
        auto add_edge = [&](ParticleBatch& to, std::size_t owner, bool last) {
            const ParticleBatch& b = last ? e[owner].last_col : e[owner].first_col;
            to.append(b, 0, b.size());
            const std::size_t col = last ? slabs_[owner].end_col - 1 : slabs_[owner].first_col;
            const auto& arr = arrivals[owner];
            for (std::size_t i = 0; i < arr.size(); ++i)
                if (grid_.cell_of_key(arr.key(i))[0] == col) to.append(arr, i, 1);
        };
        for (std::size_t d = 0; d < D; ++d) {
            incoming[d] = arrivals[d];
            if (slabs_[d].empty()) continue;
            for (std::size_t l = d; l-- > 0;)
                if (!slabs_[l].empty()) {
                    add_edge(incoming[d], l, true);
                    break;
                }
            for (std::size_t r = d + 1; r < D; ++r)
                if (!slabs_[r].empty()) {
                    add_edge(incoming[d], r, false);
                    break;
                }
        }
    }
    // 4. Leavers out, arrivals and ghosts in, sort again: [ghosts | owned | ghosts].
    {
        PhaseTimer t(phases_, "exchange: write arrivals and ghosts");
        for (std::size_t d = 0; d < D; ++d) {
            Slab& s = slabs_[d];
            auto& ps = *s.store;
            const Edges& x = e[d];
            s.cells->mark_invalid(ps, 0, x.a0);
            s.cells->mark_invalid(ps, x.a1, x.nv);
            ps.ranges = device::ParticleRanges{0, x.nv, 0};
            ps.reserve(x.nv + incoming[d].size());
            write_range(ps, x.nv, incoming[d]);
            s.cells->enqueue_sort(ps, x.nv + incoming[d].size(), 0, x.nv + incoming[d].size());
        }
    }
    {
        PhaseTimer t(phases_, "exchange: second sort and cell tables");
        for (std::size_t d = 0; d < D; ++d) {
            Slab& s = slabs_[d];
            auto& ps = *s.store;
            const std::size_t n = e[d].nv + incoming[d].size();
            const auto at = s.cells->locate(ps, n, {column_key(s.first_col), column_key(s.end_col), invalid});
            ps.ranges = device::ParticleRanges{at[0], at[1] - at[0], at[2] - at[1]};
            s.cells->build_tables(ps, at[2]);
        }
    }
    return removed;
}

void SlabDriver::forces() {
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        Slab& s = slabs_[d];
        const int repeat = d < options_.slowdown.size() ? std::max(1, options_.slowdown[d]) : 1;
        for (int k = 0; k < repeat; ++k) s.physics->forces(*s.store, *s.cells, s.store->scratch);
        if (options_.serialize) s.device->finish();
    }
}

StepOutcome SlabDriver::kick(double dt) {
    StepOutcome out;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        Slab& s = slabs_[d];
        const auto k = s.physics->kick(*s.store, dt);
        out.kick.max_speed2 = std::max(out.kick.max_speed2, k.max_speed2);
        out.kick.max_accel2 = std::max(out.kick.max_accel2, k.max_accel2);
        out.kick.kinetic_energy += k.kinetic_energy;
        out.kick.fluid += k.fluid;
        if (k.bad_index >= 0 && out.kick.bad_index < 0) {
            out.kick.bad_index = k.bad_index;
            out.bad_slab = d;
        }
    }
    return out;
}

StepOutcome SlabDriver::start() {
    const std::size_t removed = redistribute();
    forces();
    StepOutcome out = kick(0.0);
    out.removed = removed;
    return out;
}

StepOutcome SlabDriver::step(double dt) {
    if (options_.cut_schedule && slabs_.size() > 1) {
        const auto c = options_.cut_schedule(steps_, columns());
        if (c.size() != slabs_.size() + 1 || c.front() != 0 || c.back() != columns() || !std::is_sorted(c.begin(), c.end()))
            throw Error("cut schedule: cuts must be devices + 1 non-decreasing columns from 0 to the column count");
        for (std::size_t d = 0; d < slabs_.size(); ++d) {
            slabs_[d].first_col = c[d];
            slabs_[d].end_col = c[d + 1];
        }
    }
    for (auto& s : slabs_) s.physics->kick_drift(*s.store, dt);
    const std::size_t removed = redistribute();
    StepOutcome out;
    std::vector<double> before(slabs_.size());
    for (std::size_t d = 0; d < slabs_.size(); ++d)
        if (slabs_.size() > 1) {
            const auto& st = slabs_[d].device->profiler().stats();
            auto it = st.find("sph.forces");
            before[d] = it == st.end() ? 0.0 : it->second.seconds;
        }
    {
        PhaseTimer t(phases_, "forces and kick");
        forces();
        out = kick(dt);
    }
    out.removed = removed;
    ++steps_;
    if (slabs_.size() > 1) {
        for (std::size_t d = 0; d < slabs_.size(); ++d) {
            const auto& st = slabs_[d].device->profiler().stats();
            auto it = st.find("sph.forces");
            slabs_[d].force_seconds = (it == st.end() ? 0.0 : it->second.seconds) - before[d];
        }
        PhaseTimer t(phases_, "balance");
        if (!options_.cut_schedule) rebalance(steps_);
    }
    return out;
}

balance::ColumnProfile SlabDriver::column_profile() {
    // Particles per column: the sorted keys put each column in one contiguous range, so its count
    // is a difference of two lower bounds (one search per column, no atomics). Boundary particles
    // never move, so the fluid count is the rest.
    const std::size_t columns = grid_.params().n_s;
    balance::ColumnProfile p;
    p.work.assign(columns, 0.0);
    p.particles.assign(columns, 0);
    for (auto& s : slabs_) {
        if (s.empty()) continue;
        std::vector<std::uint32_t> thresholds;
        for (std::size_t c = s.first_col; c <= s.end_col; ++c) thresholds.push_back(column_key(c));
        const auto at = s.cells->locate(*s.store, s.store->ranges.active(), thresholds);
        for (std::size_t c = s.first_col; c < s.end_col; ++c) {
            const std::size_t n = at[c - s.first_col + 1] - at[c - s.first_col];
            const std::size_t b = std::min(n, boundary_per_column_[c]);
            p.particles[c] = n;
            p.work[c] = balance::column_work(n - b, b);
        }
    }
    return p;
}

void SlabDriver::rebalance(std::uint64_t step) {
    const auto profile = column_profile();
    std::vector<balance::DeviceSample> samples;
    for (auto& s : slabs_) {
        balance::DeviceSample x;
        x.compute_seconds = s.force_seconds;
        double work = 0;
        for (std::size_t c = s.first_col; c < s.end_col; ++c) work += profile.work[c];
        x.work = work;
        x.particles = s.store->ranges.owned;
        // Capacity: what the device's memory holds at ~100 bytes per particle, leaving a quarter free.
        x.capacity_particles = static_cast<std::size_t>(static_cast<double>(s.device->info().global_memory) * 0.75 / 100.0);
        samples.push_back(x);
    }
    const auto decision = balancer_->step(samples, profile);
    if (log_) log_->write(step, samples, decision);
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        slabs_[d].first_col = decision.cuts[d];
        slabs_[d].end_col = decision.cuts[d + 1];
    }
}

Particles SlabDriver::download() {
    Particles all;
    for (auto& s : slabs_) {
        const Particles p = s.store->download();
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    }
    return all;
}

std::vector<std::array<float, 2>> SlabDriver::probe(const std::vector<std::array<double, 3>>& points) {
    std::vector<std::array<float, 2>> out(points.size(), {0.0f, 0.0f});
    // Each point is evaluated on the device owning its column (which holds the ghosts it needs).
    std::vector<std::vector<std::size_t>> which(slabs_.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::array<float, 3> off{};
        const auto key = grid_.locate(points[i], off);
        if (key == grid_.params().invalid_key) continue;
        which[owner_of(key)].push_back(i);
    }
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (which[d].empty()) continue;
        std::vector<std::array<double, 3>> pts;
        for (auto i : which[d]) pts.push_back(points[i]);
        const auto r = slabs_[d].physics->probe(*slabs_[d].store, *slabs_[d].cells, pts);
        for (std::size_t k = 0; k < pts.size(); ++k) out[which[d][k]] = r[k];
    }
    return out;
}

}  // namespace clsph::multi
