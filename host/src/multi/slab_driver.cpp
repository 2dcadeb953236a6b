#include "multi/slab_driver.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <mutex>
#include <optional>

namespace clsph::multi {
namespace {
// Adds the wall time of a scope to one phase's total.
class PhaseTimer {
public:
    PhaseTimer(std::map<std::string, double>& phases, const char* name)
        : phases_(phases), name_(name), start_(std::chrono::steady_clock::now()) {}
    ~PhaseTimer() { stop(); }
    void stop() {
        if (stopped_) return;
        stopped_ = true;
        phases_[name_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    PhaseTimer(const PhaseTimer&) = delete;
    PhaseTimer& operator=(const PhaseTimer&) = delete;

private:
    std::map<std::string, double>& phases_;
    const char* name_;
    std::chrono::steady_clock::time_point start_;
    bool stopped_ = false;
};

// The device's profiled total for one launch name since the profiler was last cleared (waits for
// the launches still pending).
double profiled_seconds(cl_rt::Device& device, const std::string& name) {
    const auto& st = device.profiler().stats();
    auto it = st.find(name);
    return it == st.end() ? 0.0 : it->second.seconds;
}

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
    // A device may be left idle when even its narrowest slab would slow every step (a CPU next to a
    // GPU); the balancer does so only on a calibration or enough measured steps (balance/options.hpp).
    bo.allow_idle = true;
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
    slabs_.resize(D);
    for (std::size_t d = 0; d < D; ++d) {
        Slab& s = slabs_[d];
        s.device = devices[d];
        const std::size_t capacity = D == 1 ? p.size() : static_cast<std::size_t>(
            static_cast<double>(p.size()) / static_cast<double>(D) * (1.0 + options.headroom));
        s.store = std::make_unique<device::ParticleStore>(*s.device, grid, std::max<std::size_t>(capacity, 1), options.headroom);
        s.cells = std::make_unique<device::CellPipeline>(*s.device, grid);
        s.physics = std::make_unique<device::Physics>(*s.device, grid, scene, options.interaction);
        if (D > 1) s.device->profiler().enable(true);  // the balancer needs each force pass's time
    }
    // Devices of different speeds must not start from an equal split (a CPU next to a GPU would
    // hold half the particles for the first steps): time each one on samples of the scene first.
    if (D > 1 && bo.mode == balance::Mode::dynamic) calibrate(p, key, profile);
    const auto cuts = D == 1 ? std::vector<std::size_t>{0, columns} : balancer_->initial_cuts(profile);
    for (std::size_t d = 0; d < D; ++d) {
        Slab& s = slabs_[d];
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
        s.store->upload(mine);
    }
    if (!options.balance_log.empty()) {
        log_file_ = std::make_unique<std::ofstream>(options.balance_log);
        if (!*log_file_) throw Error("--balance-log: cannot write " + options.balance_log);
        log_ = std::make_unique<balance::BalanceLog>(*log_file_, D);
    }
}

void SlabDriver::calibrate(const Particles& p, const std::vector<std::uint32_t>& key,
                           const balance::ColumnProfile& profile) {
    // Samples are whole columns around the column that halves the work (so they look like the
    // scene: the same neighbour counts, fluid and walls), growing 4x per round from 4096 particles
    // until a device's force pass takes 20 ms, or the sample is the whole scene (at most 4 M
    // particles). The last two rounds give fixed + per-unit cost: a GPU is timed at sizes that fill
    // it, a CPU stops early. Set-up cost: about 2 x (the largest round) per device.
    const std::size_t columns = grid_.params().n_s, invalid = grid_.params().invalid_key;
    std::vector<std::vector<std::uint32_t>> by_column(columns);
    for (std::size_t i = 0; i < p.size(); ++i)
        if (key[i] != invalid) by_column[grid_.cell_of_key(key[i])[0]].push_back(static_cast<std::uint32_t>(i));
    double total = 0;
    for (double w : profile.work) total += w;
    std::size_t mid = 0;
    for (double acc = 0; mid + 1 < columns && acc + profile.work[mid] < 0.5 * total; ++mid) acc += profile.work[mid];
    auto sample_of = [&](std::size_t want, double& work) {
        std::size_t lo = mid, hi = mid, count = 0;
        work = 0;
        while (count < want && (lo > 0 || hi < columns)) {
            const bool right = hi < columns && (lo == 0 || hi - mid <= mid - lo);
            const std::size_t c = right ? hi++ : --lo;
            count += by_column[c].size();
            work += profile.work[c];
        }
        Particles out;
        for (std::size_t c = lo; c < hi; ++c)
            for (std::uint32_t i : by_column[c])
                out.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
        return out;
    };
    const std::size_t valid = p.size();
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        Slab& s = slabs_[d];
        // The test slowdown (DriverOptions::slowdown) is left out on purpose: it stands for a device
        // that becomes slow after the start, which the dynamic balancer must notice by itself.
        const int repeat = 1;
        std::vector<std::array<double, 2>> points;  // (work, seconds)
        std::size_t previous = 0;
        for (std::size_t want = std::min<std::size_t>(valid, 4096);; want *= 4) {
            double work = 0;
            const Particles sample = sample_of(want, work);
            if (sample.size() == previous) break;  // the whole scene already
            previous = sample.size();
            s.store->upload(sample);
            s.cells->run(*s.store);
            double seconds = 0;
            for (int round = 0; round < 2; ++round) {  // the first compiles and warms up
                const double before = profiled_seconds(*s.device, "sph.forces");
                for (int k = 0; k < repeat; ++k) s.physics->forces(*s.store, *s.cells, s.store->scratch);
                s.device->finish();
                seconds = profiled_seconds(*s.device, "sph.forces") - before;
            }
            if (work > 0 && seconds > 0) points.push_back({work, seconds});
            if (sample.size() >= valid || want >= (std::size_t{1} << 22) || (points.size() >= 2 && seconds >= 0.02)) break;
        }
        if (points.empty()) continue;
        const auto& b = points.back();
        double per_unit = b[1] / b[0], fixed = 0;
        if (points.size() >= 2) {
            const auto& a = points[points.size() - 2];
            const double slope = (b[1] - a[1]) / (b[0] - a[0]);
            if (slope > 0 && b[0] > a[0] && b[1] - slope * b[0] >= 0) {
                per_unit = slope;
                fixed = b[1] - slope * b[0];
            }
        }
        balancer_->calibrate(d, fixed, per_unit);
        s.calibration = {fixed, per_unit, total};
    }
    for (auto& s : slabs_) s.device->profiler().clear();
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

std::size_t SlabDriver::redistribute(const PerDevice& then) {
    const std::size_t D = slabs_.size();
    const std::uint32_t invalid = grid_.params().invalid_key;
    std::size_t removed = 0;
    moved_ = 0;
    moved_bytes_ = 0;
    // One device, or every device but one idle (a CPU next to a GPU, say): the busy one holds every
    // column and steps alone, with no exchange; with several the balancer still runs (it may hand
    // columns back) and gets the column positions.
    if (rebalance_due_) {
        PhaseTimer t(phases_, "balance");
        rebalance(steps_);
        rebalance_due_ = false;
    }
    std::size_t busy = 0, busy_slab = 0;
    for (std::size_t d = 0; d < D; ++d)
        if (!slabs_[d].empty() || slabs_[d].store->ranges.active() > 0) {
            ++busy;
            busy_slab = d;
        }
    if (D == 1 || (busy == 1 && slabs_[busy_slab].first_col == 0 && slabs_[busy_slab].end_col == columns())) {
        PhaseTimer t(phases_, "sort (one device busy)");
        Slab& s = slabs_[busy_slab];
        auto& ps = *s.store;
        std::vector<std::uint32_t> thresholds;
        for (std::size_t c = s.first_col; c <= s.end_col && D > 1; ++c) thresholds.push_back(column_key(c));
        thresholds.push_back(invalid);
        const auto at = s.cells->sort_particles(ps, ps.ranges.active(), ps.ranges.first_owned(), ps.ranges.end_owned(),
                                                thresholds);
        removed = ps.ranges.owned - at.back();
        ps.ranges = device::ParticleRanges{0, at.back(), 0};
        s.cells->build_tables(ps, at.back());
        if (D > 1) {
            s.column_at.assign(at.begin(), at.end() - 1);
            s.columns_first = s.first_col;
            s.columns_end = s.end_col;
            windowed_ready_ = true;
        }
        for_each_device(then);
        return removed;
    }
    if (options_.exchange != "sort" && windowed_ready_) {
        if (const auto r = redistribute_windowed(then)) return *r;
    }
    removed = redistribute_sorted();
    for_each_device(then);
    return removed;
}

std::vector<SlabDriver::Need> SlabDriver::needs() const {
    // Each device e needs the columns [lo, hi): its own [first, end) and one column either side (the
    // support radius is one column), which belongs to the nearest non-empty neighbour. An empty
    // device needs nothing.
    std::vector<Need> need(slabs_.size());
    for (std::size_t e = 0; e < slabs_.size(); ++e) {
        const Slab& s = slabs_[e];
        if (s.empty()) continue;
        need[e] = {s.first_col > 0 ? s.first_col - 1 : 0, s.first_col, s.end_col, std::min(s.end_col + 1, columns())};
    }
    return need;
}

std::size_t SlabDriver::redistribute_sorted() {
    const std::size_t D = slabs_.size();
    const std::uint32_t invalid = grid_.params().invalid_key;
    std::size_t removed = 0;
    // 1. Sort each device's owned particles (stale ghosts dropped): columns ascending, so what every
    //    device needs from it is one contiguous range. All devices sort at once (the balancer has
    //    already moved the cuts: redistribute()).
    cl_rt::EventSet located;
    PhaseTimer t1(phases_, "exchange: sort and locate");
    for (std::size_t d = 0; d < D; ++d) {
        auto& ps = *slabs_[d].store;
        slabs_[d].cells->enqueue_sort(ps, ps.ranges.active(), ps.ranges.first_owned(), ps.ranges.end_owned());
        slabs_[d].device->flush();
    }
    const auto need = needs();
    std::vector<std::uint32_t> thresholds;
    for (std::size_t e = 0; e < D; ++e)
        for (std::size_t c : {need[e].lo, need[e].first, need[e].end, need[e].hi}) thresholds.push_back(column_key(c));
    thresholds.push_back(invalid);
    for (std::size_t d = 0; d < D; ++d) {
        auto& ps = *slabs_[d].store;
        slabs_[d].cells->enqueue_locate(ps, ps.ranges.active(), thresholds, located);
    }
    located.wait("sorting particles before the exchange", options_.wait_mode);
    t1.stop();
    // at(d, e, k): position in device d's sorted particles of device e's k-th column bound
    // (0 lo, 1 first, 2 end, 3 hi).
    auto at = [&](std::size_t d, std::size_t e, int k) -> std::size_t {
        const auto& l = slabs_[d].cells->located();
        return l.empty() ? 0 : l[4 * e + static_cast<std::size_t>(k)];
    };
    for (std::size_t d = 0; d < D; ++d) {
        const auto& l = slabs_[d].cells->located();
        const std::size_t valid = l.empty() ? 0 : l[4 * D];
        removed += slabs_[d].store->ranges.owned - valid;
    }
    // 2. Every device's share of every other device's needs, read into pinned host memory as one
    //    block per (sender, receiver) pair: [pos | velrho | accel | id], in the sender's pinned
    //    memory (the receiver's measured the same: BENCHMARKS.md, second pass).
    struct Segment { std::size_t d, e, lo, hi; unsigned char* base; };
    std::vector<Segment> segments;
    std::vector<std::size_t> incoming(D, 0), before(D, 0), mine(D, 0), after(D, 0), staged(D, 0);
    for (std::size_t e = 0; e < D; ++e)
        for (std::size_t d = 0; d < D; ++d) {
            before[e] += at(d, e, 1) - at(d, e, 0);
            mine[e] += at(d, e, 2) - at(d, e, 1);
            after[e] += at(d, e, 3) - at(d, e, 2);
            if (d == e || at(d, e, 3) == at(d, e, 0)) continue;
            segments.push_back({d, e, at(d, e, 0), at(d, e, 3), nullptr});
            incoming[e] += at(d, e, 3) - at(d, e, 0);
            staged[d] += at(d, e, 3) - at(d, e, 0);
        }
    while (staging_.size() < D) staging_.push_back(std::make_unique<cl_rt::PinnedHost>());
    {
        std::vector<std::size_t> used(D, 0);
        for (std::size_t d = 0; d < D; ++d) staging_[d]->reserve(*slabs_[d].device, staged[d] * kStagedBytesPerParticle);
        for (auto& g : segments) {
            const std::size_t owner = g.d;
            g.base = staging_[owner]->data() + used[owner];
            used[owner] += (g.hi - g.lo) * kStagedBytesPerParticle;
        }
    }
    {
        PhaseTimer t(phases_, "exchange: read to pinned host");
        cl_rt::EventSet read;
        for (const auto& g : segments) {
            auto& ps = *slabs_[g.d].store;
            read_block(g.d, {ps.pos, ps.velrho, ps.accel, ps.id}, g.lo, g.hi - g.lo, g.base, g.e, read);
        }
        read.wait("reading particles for the neighbouring devices", options_.wait_mode);
    }
    // 3. Each device keeps its own needed range in place, takes the blocks after it and sorts again:
    //    [ghosts | owned | ghosts]. The tables' cell count and the column profile (the balancer's
    //    input) are read back together.
    {
        PhaseTimer t(phases_, "exchange: write and sort again");
        cl_rt::EventSet counted;
        for (std::size_t e = 0; e < D; ++e) {
            Slab& s = slabs_[e];
            auto& ps = *s.store;
            const std::size_t k0 = at(e, e, 0), k1 = at(e, e, 3), n = incoming[e];
            ps.ranges = device::ParticleRanges{0, k1, 0};  // what reserve() keeps
            ps.reserve(k1 + n);
            std::size_t to = k1;
            for (const auto& g : segments) {
                if (g.e != e) continue;
                const std::size_t m = g.hi - g.lo;
                write_block(*s.device, {ps.pos, ps.velrho, ps.accel, ps.id}, g.base, m, to, counted);
                to += m;
            }
            s.cells->enqueue_sort(ps, k1 + n, k0, k1 + n);
            ps.ranges = device::ParticleRanges{before[e], mine[e], after[e]};
            s.cells->enqueue_count_cells(ps, ps.ranges.active(), counted);
            enqueue_column_positions(s, ps.ranges.active(), counted);
        }
        counted.wait("sorting particles after the exchange", options_.wait_mode);
        for (std::size_t e = 0; e < D; ++e) {
            slabs_[e].cells->finish_tables(*slabs_[e].store, slabs_[e].store->ranges.active());
            remember_columns(slabs_[e]);
        }
        windowed_ready_ = true;
    }
    return removed;
}

void SlabDriver::read_block(std::size_t sender, const BlockBuffers& src, std::size_t from, std::size_t m,
                            unsigned char* base, std::size_t receiver, cl_rt::EventSet& done, cl_rt::Device::On on) {
    // Particles [from, from + m) of the sender's four arrays into a staged block
    // [pos | velrho | accel | id] (acceleration too: arrivals need it for their second kick).
    const std::size_t f4 = 4 * sizeof(float), u = sizeof(std::uint32_t);
    auto& dev = *slabs_[sender].device;
    dev.read_async(src.pos, base, m * f4, from * f4, done, on);
    dev.read_async(src.velrho, base + m * f4, m * f4, from * f4, done, on);
    dev.read_async(src.accel, base + 2 * m * f4, m * f4, from * f4, done, on);
    dev.read_async(src.id, base + 3 * m * f4, m * u, from * u, done, on);
    std::lock_guard<std::mutex> lock(counts_mutex_);  // one host thread per device may be here
    moved_ += m;
    moved_bytes_ += m * kStagedBytesPerParticle;
    slabs_[receiver].received_bytes += m * kStagedBytesPerParticle;
}

void SlabDriver::write_block(cl_rt::Device& device, const BlockBuffers& dst, const unsigned char* base, std::size_t m,
                             std::size_t to, cl_rt::EventSet& done, cl_rt::Device::On on) {
    // A staged block [pos | velrho | accel | id] of m particles, written at particle `to`.
    const std::size_t f4 = 4 * sizeof(float), u = sizeof(std::uint32_t);
    device.write_async(dst.pos, base, m * f4, to * f4, done, on);
    device.write_async(dst.velrho, base + m * f4, m * f4, to * f4, done, on);
    device.write_async(dst.accel, base + 2 * m * f4, m * f4, to * f4, done, on);
    device.write_async(dst.id, base + 3 * m * f4, m * u, to * u, done, on);
}

void SlabDriver::enqueue_column_positions(Slab& s, std::size_t n, cl_rt::EventSet& done) {
    // Where each owned column begins in the sorted particles [0, n): the next step's windows and
    // the balancer's column profile (remember_columns keeps them).
    std::vector<std::uint32_t> cols;
    for (std::size_t c = s.first_col; c <= s.end_col && !s.empty(); ++c) cols.push_back(column_key(c));
    s.cells->enqueue_locate(*s.store, n, cols, done);
}

void SlabDriver::remember_columns(Slab& s) {
    const auto& at = s.cells->located();
    s.column_at.assign(at.begin(), at.end());
    s.columns_first = s.first_col;
    s.columns_end = s.end_col;
    if (s.empty() || s.column_at.size() != s.end_col - s.first_col + 1) {
        s.column_at.clear();
        s.columns_first = s.columns_end = 0;
    }
}

std::optional<std::size_t> SlabDriver::redistribute_windowed(const PerDevice& then) {
    // One sort per step. Particles move less than a column per step (CFL), so what device e needs
    // from device d (its particles now in e's columns [lo, hi)) was, before the drift, in d's
    // columns [lo - 1, hi + 1): a window of d's still-sorted array, known from the last step's
    // column positions. Each window is compacted on d (flag, scan, gather into an outbox), read
    // to pinned host memory, written after e's particles, and one sort per device then orders
    // [ghosts | owned | ghosts] and drops what e no longer needs.
    const std::size_t D = slabs_.size();
    const auto need = needs();
    struct Block { std::size_t d, e, index, base; };
    std::vector<Block> blocks;
    // Devices that may take the overlapped path (below) sort the keys of what they keep right after
    // the gathers, so the counts' round trip runs beside that sort; only moving the particles into
    // that order has to wait for the counts (it needs the room for the left arrivals).
    std::vector<char> presorted(D, 0);
    for (std::size_t d = 0; d < D; ++d) {
        const Slab& s = slabs_[d];
        presorted[d] = options_.exchange == "overlap" && !s.empty() && s.store->ranges.active() > 0 &&
                       s.column_at.size() == s.columns_end - s.columns_first + 1 && s.columns_end - s.columns_first >= 4;
    }
    {
        PhaseTimer t(phases_, "exchange: settle and gather");
        cl_rt::EventSet gathered;
        std::vector<std::vector<Block>> sent(D);
        for_each_device([&](std::size_t d) {
            Slab& s = slabs_[d];
            auto& ps = *s.store;
            s.cells->enqueue_settle(ps, column_key(need[d].lo), need[d].hi > need[d].lo ? column_key(need[d].hi) : 0, gathered);
            struct Window { std::size_t e, first, end; };
            std::vector<Window> windows;
            std::size_t total = 0;
            if (!s.column_at.empty())
                for (std::size_t e = 0; e < D; ++e) {
                    if (e == d || need[e].hi <= need[e].lo) continue;
                    const std::size_t c0 = std::max(need[e].lo > 0 ? need[e].lo - 1 : 0, s.columns_first);
                    const std::size_t c1 = std::min(need[e].hi + 1, s.columns_end);
                    if (c1 <= c0) continue;
                    const std::size_t first = s.column_at[c0 - s.columns_first], end = s.column_at[c1 - s.columns_first];
                    if (end > first) {
                        windows.push_back({e, first, end});
                        total += end - first;
                    }
                }
            s.cells->begin_gathers(windows.size(), total);
            std::size_t base = 0;
            for (std::size_t k = 0; k < windows.size(); ++k) {
                const auto& w = windows[k];
                s.cells->enqueue_gather(ps, w.first, w.end, column_key(need[w.e].lo), column_key(need[w.e].hi), base, k,
                                        gathered);
                sent[d].push_back({d, w.e, k, base});
                base += w.end - w.first;
            }
            if (presorted[d])
                s.cells->enqueue_sort_keys(ps, ps.ranges.active(), ps.ranges.first_owned(), ps.ranges.end_owned(),
                                           ps.ranges.active(), column_key(need[d].lo),
                                           need[d].hi > need[d].lo ? column_key(need[d].hi) : 0, false);
            s.device->flush();
        });
        for (const auto& v : sent) blocks.insert(blocks.end(), v.begin(), v.end());
        gathered.wait("gathering particles for the neighbouring devices", options_.wait_mode);
    }
    std::size_t removed = 0;
    for (auto& s : slabs_) {
        if (s.cells->settled()[1] != 0) {
            ++fallbacks_;
            return std::nullopt;  // a particle jumped more than a column: sort first
        }
        removed += s.cells->settled()[0];
    }
    // Per receiver: particles from devices to its left and to its right (senders to the left hold
    // lower columns, so what they send lands below everything this device keeps, and the other way
    // round for the right: see the edge plan below).
    std::vector<std::size_t> staged(D, 0), from_left(D, 0), from_right(D, 0);
    for (const auto& b : blocks) {
        const std::size_t m = slabs_[b.d].cells->gather_count(b.index);
        staged[b.d] += m;
        (b.d < b.e ? from_left : from_right)[b.e] += m;
    }
    // The overlap: each device sorts the particles it keeps while the arrivals travel, leaving
    // room for them below (the left ones) and above (the right ones); afterwards only the edges,
    // where arrivals and kept particles meet, need sorting. Kept particles that now lie below
    // column first_old + 1 were, before the drift, below first_old + 2 (CFL: at most one column
    // per step, checked by the settle), so the last step's column positions bound the left edge;
    // likewise the right. A device that held nothing or a slab too narrow for the bounds to leave
    // a middle sorts everything once the arrivals are in (the plan's `edges` is false).
    struct EdgePlan { bool edges = false; std::size_t kept_all = 0, kept = 0, left = 0, right = 0, end = 0; };
    std::vector<EdgePlan> plan(D);
    for (std::size_t e = 0; e < D; ++e) {
        const Slab& s = slabs_[e];
        const auto& ps = *s.store;
        EdgePlan& p = plan[e];
        p.kept_all = ps.ranges.active();     // sorted as a whole; ghosts and leavers drop to its end
        p.kept = s.cells->settled()[2];      // of which stay (their keys lie in this device's need)
        const std::size_t last = s.columns_end - s.columns_first;
        if (!presorted[e] || p.kept == 0) continue;
        const std::size_t x = std::min<std::size_t>(p.kept, s.column_at[2] - s.column_at[0]);
        const std::size_t y = std::min<std::size_t>(p.kept, s.column_at[last] - s.column_at[last - 2]);
        p.left = from_left[e] + x;
        p.right = from_left[e] + p.kept - y;
        p.end = from_left[e] + p.kept_all + from_right[e];
        // The edges go through the reorder scratch, four arrays side by side.
        const std::size_t m = p.left + (p.end - p.right);
        p.edges = p.left < p.right && options_.exchange == "overlap" &&
                  device::CellPipeline::edge_scratch_bytes(m) <= ps.capacity() * 4 * sizeof(float);
    }
    while (staging_.size() < D) staging_.push_back(std::make_unique<cl_rt::PinnedHost>());
    for (std::size_t d = 0; d < D; ++d) staging_[d]->reserve(*slabs_[d].device, staged[d] * kStagedBytesPerParticle);
    std::vector<unsigned char*> at(blocks.size());
    {
        std::vector<std::size_t> used(D, 0);
        for (std::size_t k = 0; k < blocks.size(); ++k) {
            const auto& b = blocks[k];
            at[k] = staging_[b.d]->data() + used[b.d];
            used[b.d] += slabs_[b.d].cells->gather_count(b.index) * kStagedBytesPerParticle;
        }
    }
    {
        PhaseTimer t(phases_, "exchange: reads beside the kept sort");
        cl_rt::EventSet read;
        for_each_device([&](std::size_t d) {
            Slab& s = slabs_[d];
            auto& ps = *s.store;
            // Outboxes to pinned memory on the transfer queue (the gathers finished before the wait
            // above), while the compute queue sorts what this device keeps.
            for (std::size_t k = 0; k < blocks.size(); ++k) {
                const auto& b = blocks[k];
                if (b.d != d) continue;
                auto& c = *s.cells;
                read_block(d, {c.outbox_pos, c.outbox_velrho, c.outbox_accel, c.outbox_id}, b.base, c.gather_count(b.index),
                           at[k], b.e, read, cl_rt::Device::On::transfer);
            }
            s.device->transfer_queue().flush();
            const EdgePlan& p = plan[d];
            if (!p.edges) return;
            ps.reserve(p.end);  // keeps the sorted keys
            s.cells->enqueue_reorder(ps, p.kept_all, from_left[d]);
            s.device->flush();
        });
        read.wait("reading particles for the neighbouring devices", options_.wait_mode);
    }
    {
        PhaseTimer t(phases_, "exchange: writes, edges and tables");
        // Each device on its own host thread: a write from memory pinned in another device's
        // context may hold the thread until it is done (NVIDIA).
        for_each_device([&](std::size_t e) {
            Slab& s = slabs_[e];
            auto& ps = *s.store;
            const EdgePlan& p = plan[e];
            const std::size_t n = from_left[e] + from_right[e];
            // Arrivals into the inbox on the transfer queue: left senders first, then right ones.
            s.cells->begin_inbox(n);
            cl_rt::EventSet written;
            std::size_t to = 0;
            for (bool left : {true, false})
                for (std::size_t k = 0; k < blocks.size(); ++k) {
                    const auto& b = blocks[k];
                    if (b.e != e || (b.d < b.e) != left) continue;
                    const std::size_t m = slabs_[b.d].cells->gather_count(b.index);
                    auto& c = *s.cells;
                    write_block(*s.device, {c.inbox_pos, c.inbox_velrho, c.inbox_accel, c.inbox_id}, at[k], m, to, written,
                                cl_rt::Device::On::transfer);
                    to += m;
                }
            s.device->barrier(written);
            const std::uint32_t key_lo = column_key(need[e].lo), key_hi = need[e].hi > need[e].lo ? column_key(need[e].hi) : 0;
            const std::size_t valid = p.kept + n;
            if (p.edges) {
                // [left arrivals | kept, sorted | dropped | right arrivals], then the two edges.
                s.cells->enqueue_unpack_inbox(ps, 0, from_left[e], 0);
                s.cells->enqueue_unpack_inbox(ps, from_left[e], from_right[e], from_left[e] + p.kept_all);
                s.cells->enqueue_edge_sort(ps, p.left, p.right, p.end, from_left[e] + p.kept, from_left[e] + p.kept_all,
                                           key_lo, key_hi, p.end - p.right - (p.kept_all - p.kept));
                s.cells->enqueue_rekey(ps, valid);
            } else {
                // [everything held | arrivals], one sort that drops what is no longer needed here.
                const std::size_t active = ps.ranges.active();
                ps.reserve(active + n);
                s.cells->enqueue_unpack_inbox(ps, 0, n, active);
                s.cells->enqueue_sort(ps, active + n, ps.ranges.first_owned(), ps.ranges.end_owned(), active, key_lo, key_hi,
                                      false);
            }
            // The cell count and the column positions: this device's own round trip, waited for on
            // its own thread, which then enqueues the rest of the tables at once.
            cl_rt::EventSet counted;
            for (auto& ev : written.events_of(*s.device)) counted.add(*s.device, ev);
            ps.ranges = device::ParticleRanges{0, valid, 0};
            s.cells->enqueue_count_cells(ps, valid, counted);
            enqueue_column_positions(s, valid, counted);
            counted.wait("sorting particles after the exchange", options_.wait_mode);
            const auto& l = s.cells->located();
            if (s.empty() || l.size() < 2) {
                ps.ranges = device::ParticleRanges{0, 0, 0};
            } else {
                ps.ranges = device::ParticleRanges{l.front(), l.back() - l.front(), valid - l.back()};
            }
            s.cells->finish_tables(ps, ps.ranges.active());
            remember_columns(s);
            then(e);
        });
    }
    return removed;
}

void SlabDriver::for_each_device(const std::function<void(std::size_t)>& work) {
    // One thread suffices where at most one device has anything to do (a GPU next to an idle CPU):
    // handing work to the other threads would only add their wake-ups to every phase.
    std::size_t busy = 0;
    for (const auto& s : slabs_) busy += !s.empty() || s.store->ranges.active() > 0;
    if (slabs_.size() == 1 || options_.serialize || busy <= 1) {
        for (std::size_t d = 0; d < slabs_.size(); ++d) work(d);
        return;
    }
    if (!threads_) threads_ = std::make_unique<DeviceThreads>(slabs_.size());
    threads_->run(work);
}

void SlabDriver::enqueue_forces_and_kick(std::size_t d, double dt, cl_rt::EventSet& done) {
    // On the device's own host thread, as soon as its tables are enqueued: the force pass, the
    // second kick and its reductions; then, while the force pass runs, the profiler folds in the
    // step's finished launches (so reading this step's force time after the wait is quick).
    Slab& s = slabs_[d];
    const int repeat = d < options_.slowdown.size() ? std::max(1, options_.slowdown[d]) : 1;
    for (int k = 0; k < repeat; ++k) s.physics->forces(*s.store, *s.cells, s.store->scratch);
    if (options_.serialize) s.device->finish();
    if (s.store->ranges.owned > 0) s.physics->enqueue_kick(*s.store, dt, done);  // idle devices rest
    s.device->flush();
    if (slabs_.size() > 1) s.device->profiler().collect_finished();
}

StepOutcome SlabDriver::finish_kick(cl_rt::EventSet& done) {
    done.wait("the second kick", options_.wait_mode);
    StepOutcome out;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (slabs_[d].store->ranges.owned == 0) continue;
        const auto k = slabs_[d].physics->kick_result();
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
    cl_rt::EventSet done;
    const std::size_t removed = redistribute([&](std::size_t d) { enqueue_forces_and_kick(d, 0.0, done); });
    StepOutcome out = finish_kick(done);
    out.removed = removed;
    for (auto& s : slabs_) {  // the first step's force time counts from here
        s.force_total_seen = profiled_seconds(*s.device, "sph.forces");
    }
    return out;
}

StepOutcome SlabDriver::step(double dt) {
    if (options_.fail_at_step != 0 && steps_ + 1 == options_.fail_at_step) {
        const std::size_t d = std::min(options_.fail_device, slabs_.size() - 1);
        throw DeviceError(CL_OUT_OF_RESOURCES, "launching kernel 'sph.kick_drift' on " + slabs_[d].device->label() +
                                                   ": CL_OUT_OF_RESOURCES (-5) (a simulated failure, for tests)");
    }
    if (options_.cut_schedule && slabs_.size() > 1) {
        const auto c = options_.cut_schedule(steps_, columns());
        if (c.size() != slabs_.size() + 1 || c.front() != 0 || c.back() != columns() || !std::is_sorted(c.begin(), c.end()))
            throw Error("cut schedule: cuts must be devices + 1 non-decreasing columns from 0 to the column count");
        for (std::size_t d = 0; d < slabs_.size(); ++d) {
            slabs_[d].first_col = c[d];
            slabs_[d].end_col = c[d + 1];
        }
    }
    for_each_device([&](std::size_t d) {  // the balancer runs while the devices drift
        slabs_[d].physics->kick_drift(*slabs_[d].store, dt);
        slabs_[d].device->flush();
    });
    cl_rt::EventSet done;
    const std::size_t removed = redistribute([&](std::size_t d) { enqueue_forces_and_kick(d, dt, done); });
    StepOutcome out;
    {
        PhaseTimer t(phases_, "forces and kick");
        out = finish_kick(done);
    }
    out.removed = removed;
    ++steps_;
    if (slabs_.size() > 1) {
        // This step's force pass: the growth of the profiler's total since the last step (read
        // after the kick's wait; reading it before the force pass would wait for the queue).
        for (auto& s : slabs_) {
            const double total = profiled_seconds(*s.device, "sph.forces");
            s.force_seconds = total - (total >= s.force_total_seen ? s.force_total_seen : 0.0);  // 0: cleared
            s.force_total_seen = total;
        }
        rebalance_due_ = !options_.cut_schedule;  // at the start of the next step's exchange
    }
    return out;
}

balance::ColumnProfile SlabDriver::column_profile() {
    // Particles per column: the sorted keys put each column in one contiguous range, so its count
    // is a difference of two lower bounds, located after the exchange's second sort. Boundary
    // particles never move, so the fluid count is the rest.
    const std::size_t columns = grid_.params().n_s;
    balance::ColumnProfile p;
    p.work.assign(columns, 0.0);
    p.particles.assign(columns, 0);
    for (auto& s : slabs_) {
        if (s.empty()) continue;
        const auto& at = s.column_at;
        if (s.columns_first != s.first_col || s.columns_end != s.end_col || at.size() != s.end_col - s.first_col + 1) continue;
        for (std::size_t c = s.first_col; c < s.end_col; ++c) {
            const std::size_t n = at[c - s.first_col + 1] - at[c - s.first_col];
            const std::size_t b = std::min<std::size_t>(n, boundary_per_column_[c]);
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
