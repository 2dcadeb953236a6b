#include "multi/exchange.hpp"
#include "clsph/error.hpp"
#include "device/sizing.hpp"

#include <algorithm>

namespace clsph::multi {
namespace {
bool ranges_hold(const device::KeyRange& k, std::uint32_t key) { return key >= k.lo && key < k.hi; }
}  // namespace

Exchange::Exchange(const Partition& partition, std::vector<Slab>& slabs, ForEachDevice for_each_device,
                   cl_rt::EventSet::Mode wait, PhaseTotals& phases, bool always_wide, RankMap ranks)
    : partition_(partition),
      slabs_(slabs),
      for_each_device_(std::move(for_each_device)),
      wait_(wait),
      phases_(phases),
      always_wide_(always_wide),
      ranks_(std::move(ranks)) {}

Link& Exchange::link(std::size_t from, std::size_t to) {
    auto& l = links_[{from, to}];
    if (!l) l = std::make_unique<StagedLink>(*slabs_[from].device, *slabs_[to].device);
    return *l;
}

std::size_t Exchange::sort_uploaded() {
    const std::uint32_t invalid = partition_.grid().params().invalid_key;
    std::size_t removed = 0;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (!ranks_.here(d)) continue;
        Slab& s = slabs_[d];
        auto& ps = *s.store;
        const std::size_t n = ps.ranges.active();
        std::vector<std::uint32_t> thresholds;
        for (std::size_t c = s.first_col; slabs_.size() > 1 && !s.empty() && c <= s.end_col; ++c)
            thresholds.push_back(partition_.column_key(c));
        thresholds.push_back(invalid);
        const auto at = s.cells->sort_particles(ps, n, 0, n, thresholds);
        removed += n - at.back();
        ps.ranges = device::ParticleRanges{0, at.back(), 0};
        s.column_at.assign(at.begin(), at.end() - 1);
        s.columns_first = s.first_col;
        s.columns_end = s.end_col;
        if (s.empty() || !s.columns_known()) s.column_at.clear();
    }
    if (ranks_.ranks) {
        std::vector<std::uint64_t> n{removed};
        ranks_.ranks->sum(n);
        removed = static_cast<std::size_t>(n[0]);
    }
    return removed;
}

std::vector<Exchange::Refresh> Exchange::refreshes() const {
    // Device e's ghosts are the particles of columns [lo, first) and [end, hi) of its need, in
    // sorted order: each owner's part, in column order, is where the owner's column positions say.
    std::vector<Refresh> out;
    for (std::size_t e = 0; e < slabs_.size(); ++e) {
        const Slab& r = slabs_[e];
        if (!ranks_.here(e) || r.empty()) continue;
        const Need& need = need_[e];
        const auto& held = r.store->ranges;
        for (bool left : {true, false}) {
            const std::size_t lo = left ? need.lo : need.end, hi = left ? need.first : need.hi;
            std::size_t to = left ? 0 : held.end_owned(), got = 0;
            for (std::size_t d = 0; d < slabs_.size(); ++d) {
                const Slab& s = slabs_[d];
                const std::size_t a = std::max(lo, s.first_col), b = std::min(hi, s.end_col);
                if (d == e || s.empty() || a >= b) continue;
                if (!s.columns_known() || s.columns_first != s.first_col || s.columns_end != s.end_col)
                    throw Error("internal: the tables are kept, but " + s.device->label() + "'s column positions are not its columns'");
                const std::size_t first = s.column_at[a - s.first_col], end = s.column_at[b - s.first_col];
                if (end > first) out.push_back({d, e, first, end - first, to});
                to += end - first;
                got += end - first;
            }
            if (got != (left ? held.ghosts_before : held.ghosts_after))
                throw Error("internal: the tables are kept, but " + r.device->label() + " holds " +
                            std::to_string(left ? held.ghosts_before : held.ghosts_after) + (left ? " left" : " right") +
                            " ghosts where its neighbours own " + std::to_string(got));
        }
    }
    return out;
}

void Exchange::keep(const PerDevice& then, const PerDevice& before) {
    PhaseTimer t(phases_, "exchange: tables kept, ghosts copied");
    // The copies are read on the owners' compute queues, after their drifts, and written on the
    // receivers', before their force passes: the ghosts hold their owners' particles of this step
    // in the places the last exchange gave them, so every device's tables still name them.
    const std::vector<Refresh> parts = slabs_.size() > 1 ? refreshes() : std::vector<Refresh>{};
    for (const auto& p : parts)  // made here, not on the device threads
        if (!refresh_staging_.count({p.d, p.e})) refresh_staging_[{p.d, p.e}] = std::make_unique<cl_rt::PinnedHost>();
    cl_rt::EventSet read;
    for_each_device_([&](std::size_t d) {
        Slab& s = slabs_[d];
        if (before) before(d);
        for (const auto& p : parts) {
            if (p.d != d) continue;
            auto& staging = *refresh_staging_.at({p.d, p.e});
            staging.reserve(*s.device, p.n * device::ParticleArrays::kBytesPerParticle);
            device::read_particles(*s.device, *s.store, p.first, p.n, staging.data(), read, cl_rt::Device::On::compute);
        }
        s.device->flush();
    });
    read.wait("copying the neighbouring devices' particles to their ghosts", wait_);
    for_each_device_([&](std::size_t e) {
        Slab& s = slabs_[e];
        cl_rt::EventSet written;  // in order before the force pass on the same queue
        for (const auto& p : parts)
            if (p.e == e) {
                device::write_particles(*s.device, *s.store, p.to, p.n, refresh_staging_.at({p.d, p.e})->data(), written,
                                        cl_rt::Device::On::compute);
                s.received_bytes += p.n * device::ParticleArrays::kBytesPerParticle;
            }
        s.interior_first = s.interior_end = 0;  // the force pass whole
        then(e);
    });
}

void Exchange::prepare_keep_ahead() {
    if (slabs_.size() < 2) return;
    for (const auto& p : refreshes()) {
        if (cl_rt::Relay::same_context(*slabs_[p.d].device, *slabs_[p.e].device)) continue;
        auto& staging = refresh_staging_[{p.d, p.e}];
        if (!staging) staging = std::make_unique<cl_rt::PinnedHost>();
        staging->reserve(*slabs_[p.d].device, p.n * device::ParticleArrays::kBytesPerParticle);
    }
}

void Exchange::keep_ahead(cl_rt::Relay* relay, const PerDevice& then, const PerDevice& before) {
    const std::vector<Refresh> parts = slabs_.size() > 1 ? refreshes() : std::vector<Refresh>{};
    if (!parts.empty() && !relay) throw Error("internal: the ghosts' copies ahead without a relay");
    for (std::size_t d = 0; d < slabs_.size(); ++d) before(d);
    for (const auto& p : parts) {
        auto& staging = refresh_staging_[{p.d, p.e}];
        if (!staging) staging = std::make_unique<cl_rt::PinnedHost>();
        Slab& s = slabs_[p.d];
        Slab& r = slabs_[p.e];
        std::vector<std::pair<const cl_rt::Buffer*, std::size_t>> src;
        s.store->each([&](const cl_rt::Buffer& b, std::size_t elem, const char*) { src.push_back({&b, elem}); });
        std::vector<cl_rt::Relay::Piece> pieces;
        std::size_t k = 0;
        r.store->each([&](cl_rt::Buffer& b, std::size_t elem, const char*) {
            pieces.push_back({src[k++].first, &b, p.n * elem, p.first * elem, p.to * elem});
        });
        // A staging block per pair serves every step: the sender's next read comes after its next
        // drift, which waits for this step's end on every device (the step sums), and the receiver's
        // write of this one comes before its force pass, hence before its step sums.
        relay->copy(*s.device, *r.device, pieces, *staging);
        r.received_bytes += p.n * device::ParticleArrays::kBytesPerParticle;
    }
    for (std::size_t e = 0; e < slabs_.size(); ++e) {
        slabs_[e].interior_first = slabs_[e].interior_end = 0;  // the force pass whole
        then(e);
    }
}

std::size_t Exchange::run(const PerDevice& then, const Particles* created, const PerDevice& before) {
    const std::size_t D = slabs_.size();
    need_ = partition_.needs(slabs_);
    created_ = created && created->size() > 0 ? created : nullptr;
    created_for_.assign(D, {});
    if (created_) {  // each device the new particles in the columns it needs, in their order
        const device::Grid& grid = partition_.grid();
        for (std::size_t i = 0; i < created_->size(); ++i) {
            std::array<float, 3> off{};
            const std::uint32_t key = grid.locate(created_->position[i], off);
            for (std::size_t e = 0; e < D; ++e) {
                const device::KeyRange k = partition_.keys_of(need_[e]);
                if (ranges_hold(k, key) && ranks_.here(e)) created_for_[e].push_back(i);
            }
        }
    }
    std::vector<Block> blocks;
    std::vector<char> presorted(D, 0);
    settle_and_gather(false, blocks, presorted, before);
    std::size_t removed = 0, jumped = 0;
    for (std::size_t d = 0; d < D; ++d) {
        if (!ranks_.here(d)) continue;
        removed += slabs_[d].cells->settled().left_domain;
        jumped += slabs_[d].cells->settled().jumped;
    }
    if (ranks_.ranks) {
        std::vector<std::uint64_t> n{removed, jumped};
        ranks_.ranks->sum(n);
        removed = static_cast<std::size_t>(n[0]);
        jumped = static_cast<std::size_t>(n[1]);
    }
    if ((jumped > 0 || always_wide_) && D > 1) {  // the windows may miss a particle: send from whole slabs
        blocks.clear();
        std::fill(presorted.begin(), presorted.end(), 0);
        settle_and_gather(true, blocks, presorted);
    }
    std::vector<std::size_t> from_left(D, 0), from_right(D, 0);
    for (const auto& b : blocks) {
        if (!ranks_.here(b.e)) continue;  // to another rank: below
        (b.d < b.e ? from_left : from_right)[b.e] += slabs_[b.d].cells->gather_count(b.index);
        link(b.d, b.e);  // made here, not on the device threads
    }
    if (ranks_.ranks) {
        send_remote_counts(blocks);
        for (std::size_t e = 0; e < D; ++e) {
            if (!ranks_.here(e)) continue;
            for (auto n : remote_arrivals(e, true)) from_left[e] += n;
            for (auto n : remote_arrivals(e, false)) from_right[e] += n;
        }
    }
    std::vector<Plan> plans(D);
    for (std::size_t e = 0; e < D; ++e)
        if (ranks_.here(e)) plans[e] = plan(e, presorted[e], from_left[e], from_right[e], created_for_[e].size());
    send(blocks, plans);
    {
        PhaseTimer t(phases_, "exchange: receive, merge and tables");
        for_each_device_([&](std::size_t e) { receive_and_merge(e, blocks, plans[e], then); });
    }
    return removed;
}

void Exchange::settle_and_gather(bool wide, std::vector<Block>& blocks, std::vector<char>& presorted,
                                 const PerDevice& before) {
    PhaseTimer t(phases_, "exchange: settle and gather");
    const std::size_t D = slabs_.size();
    cl_rt::EventSet gathered;
    std::vector<std::vector<Block>> sent(D);
    for_each_device_([&](std::size_t d) {
        Slab& s = slabs_[d];
        auto& ps = *s.store;
        if (before) before(d);  // the step's drift: the settle follows it in the queue
        if (!wide) s.cells->enqueue_settle(ps, partition_.keys_of(need_[d]), gathered, interior_keys(d));
        // What each other device needs from this one lies in a window: one column wider on either
        // side than its columns, within what this device owned (or, `wide`, all of that).
        struct Window { std::size_t e, first, end; };
        std::vector<Window> windows;
        std::size_t total = 0;
        for (std::size_t e = 0; e < D; ++e) {
            if (e == d || need_[e].empty()) continue;
            std::size_t first = ps.ranges.first_owned(), end = ps.ranges.end_owned();
            if (!wide) {
                if (!s.columns_known()) continue;
                const std::size_t c0 = std::max(need_[e].lo > 0 ? need_[e].lo - 1 : 0, s.columns_first);
                const std::size_t c1 = std::min(need_[e].hi + 1, s.columns_end);
                if (c1 <= c0) continue;
                first = s.column_at[c0 - s.columns_first];
                end = s.column_at[c1 - s.columns_first];
            }
            if (end > first) {
                windows.push_back({e, first, end});
                total += end - first;
            }
        }
        if (s.outbox.capacity() < total || !s.outbox.id) s.outbox.allocate(*s.device, device::sizing::box_capacity(total), "exchange outbox");
        s.cells->begin_gathers(windows.size());
        std::size_t base = 0;
        for (std::size_t k = 0; k < windows.size(); ++k) {
            const auto& w = windows[k];
            s.cells->enqueue_gather(ps, w.first, w.end, partition_.keys_of(need_[w.e]), s.outbox, base, k, gathered);
            sent[d].push_back({d, w.e, k, base});
            base += w.end - w.first;
        }
        // The keys of what this device keeps sort now, so the counts' round trip runs beside it;
        // only moving the particles into that order waits for the counts (it needs the room for
        // the left arrivals).
        presorted[d] = !wide && !s.empty() && ps.ranges.active() > 0;
        if (presorted[d])
            s.cells->enqueue_sort_keys(ps, device::SortSelection{ps.ranges.active(), ps.ranges.first_owned(),
                                                                 ps.ranges.end_owned(), ps.ranges.active(),
                                                                 partition_.keys_of(need_[d]), false});
        s.device->flush();
    });
    for (const auto& v : sent) blocks.insert(blocks.end(), v.begin(), v.end());
    gathered.wait("gathering particles for the neighbouring devices", wait_);
}

Exchange::Plan Exchange::plan(std::size_t e, bool presorted, std::size_t from_left, std::size_t from_right,
                              std::size_t created) const {
    const Slab& s = slabs_[e];
    const auto& ps = *s.store;
    Plan p;
    p.held = ps.ranges.active();  // sorted as a whole; ghosts and leavers drop to its end
    p.kept = s.cells->settled().kept;  // of which stay (their keys lie in this device's need)
    p.from_left = from_left;
    p.from_right = from_right + created;  // new particles after the right arrivals
    const std::size_t n = from_left + p.from_right;
    if (created > 0) return p;  // anywhere in the slab: one sort of everything (Merge::all)
    if (n == 0 && (p.kept == 0 || presorted)) {
        p.merge = p.kept == 0 ? Merge::empty : Merge::kept_only;
        return p;
    }
    p.merge = Merge::all;
    // Kept particles that now lie below column first_old + 1 were, before the drift, below
    // first_old + 2 (CFL: at most one column per step, checked by the settle), so the last
    // exchange's column positions bound the left edge; likewise the right. A slab too narrow for
    // the bounds to leave a middle sorts everything once the arrivals are in.
    if (!presorted || p.kept == 0 || !s.columns_known() || s.columns_end - s.columns_first < 4) return p;
    // A side without arrivals needs no edge: the kept particles are sorted already, and the
    // dropped ones after them lie beyond what stays.
    const std::size_t last = s.columns_end - s.columns_first;
    const std::size_t x = std::min<std::size_t>(p.kept, s.column_at[2] - s.column_at[0]);
    const std::size_t y = std::min<std::size_t>(p.kept, s.column_at[last] - s.column_at[last - 2]);
    p.left = from_left > 0 ? from_left + x : 0;
    p.right = from_left + p.kept - (from_right > 0 ? y : 0);
    p.end = from_right > 0 ? from_left + p.held + from_right : p.right;
    // The arrivals from the left were owned left of this slab's old first column and moved at most
    // a column: they lie below column first_old + 1; those from the right at end_old - 1 or above.
    // Only kept particles, in sorted order, lie beyond, so each edge sorts on the bits of a few
    // columns (CellPipeline::enqueue_edge_sort).
    p.left_top = partition_.column_key(s.columns_first + 1);
    p.right_bottom = partition_.column_key(s.columns_end - 1);
    // The edges go through the reorder scratch, four arrays side by side, or arrays of their own.
    const std::size_t m = p.left + (p.end - p.right);
    if (p.left < p.right && (s.cells->edges_apart() || device::CellPipeline::edge_scratch_bytes(m) <= ps.capacity() * 4 * sizeof(float)))
        p.merge = Merge::edges;
    const auto [lo, hi] = interior_columns(e);
    if (p.merge == Merge::edges && lo < hi) {
        // Where their particles lie among the kept ones once sorted: the settle counted the kept
        // particles below either column (interior_keys).
        const device::Settled& settled = s.cells->settled();
        p.overlap = true;
        p.interior_lo = lo;
        p.interior_hi = hi;
        p.run_first = from_left + settled.kept_below_lo;
        p.run_end = from_left + settled.kept_below_hi;
    }
    return p;
}

void Exchange::send(const std::vector<Block>& blocks, const std::vector<Plan>& plans) {
    PhaseTimer t(phases_, "exchange: send beside the kept sort");
    cl_rt::EventSet sent;
    for_each_device_([&](std::size_t d) {
        Slab& s = slabs_[d];
        for (const auto& b : blocks)
            if (b.d == d && ranks_.here(b.e)) links_.at({d, b.e})->send(s.outbox, b.base, s.cells->gather_count(b.index), sent);
        s.device->transfer_queue().flush();
        for (std::size_t e = 0; e < slabs_.size(); ++e)  // to other ranks: the particles once read
            if (remote_pair(d, e)) remote_send_.at({d, e})->post();
        const Plan& p = plans[d];
        if (p.merge == Merge::edges || p.merge == Merge::kept_only) {
            s.store->reserve(p.from_left + p.held + p.from_right);  // keeps the sorted keys
            s.cells->enqueue_reorder(*s.store, p.held, p.from_left);
            // The kept particles' tables and the interior's forces, while the blocks travel.
            if (p.overlap) {
                s.cells->enqueue_interior_tables(*s.store, p.from_left + p.kept, p.from_left);
                if (p.run_end > p.run_first) interior_.run(d, p.run_first, p.run_end);
            }
            s.device->flush();
        }
    });
    sent.wait("sending particles to the neighbouring devices", wait_);
}

void Exchange::receive_and_merge(std::size_t e, const std::vector<Block>& blocks, const Plan& p, const PerDevice& then) {
    Slab& s = slabs_[e];
    auto& ps = *s.store;
    auto& dev = *s.device;
    const std::size_t n = p.from_left + p.from_right;
    if (s.inbox.capacity() < n || !s.inbox.id) s.inbox.allocate(dev, device::sizing::box_capacity(n), "exchange inbox");
    // Arrivals into the inbox on the transfer queue: left senders first, then right ones. (On its
    // own host thread: a write from memory pinned in another device's context may hold the thread
    // until it is done, on NVIDIA.)
    cl_rt::EventSet written;
    // In sender order (each sender has at most one block for e), whichever rank it is on.
    std::size_t to = 0;
    for (bool left : {true, false})
        for (std::size_t d = 0; d < slabs_.size(); ++d) {
            if (d == e || (d < e) != left) continue;
            std::size_t got = 0;
            if (remote_pair(d, e)) {
                auto& l = *remote_receive_.at({d, e});
                l.receive(s.inbox, to, written);
                got = l.count();
            } else {
                const auto b = std::find_if(blocks.begin(), blocks.end(), [&](const Block& x) { return x.d == d && x.e == e; });
                if (b == blocks.end()) continue;
                Link& l = *links_.at({d, e});
                l.receive(s.inbox, to, written);
                got = l.count();
            }
            to += got;
            s.received_bytes += got * device::ParticleArrays::kBytesPerParticle;
        }
    if (!created_for_[e].empty()) {  // inlets' new particles, after every arrival
        s.inlets->write(s.inbox, to, *created_, created_for_[e]);
        to += created_for_[e].size();
    }
    dev.barrier(written);
    const device::KeyRange keys = partition_.keys_of(need_[e]);
    std::size_t valid = 0;
    switch (p.merge) {
    case Merge::empty: break;
    case Merge::kept_only: valid = p.kept; break;
    case Merge::edges:
        // [left arrivals | kept, sorted | dropped | right arrivals], then the two edges.
        device::copy_particles(dev, s.inbox, 0, ps, 0, p.from_left);
        device::copy_particles(dev, s.inbox, p.from_left, ps, p.from_left + p.held, p.from_right);
        s.cells->enqueue_edge_sort(ps, device::EdgeSort{p.left, p.right, p.end, p.from_left + p.kept, p.from_left + p.held,
                                                        p.end > p.right ? p.end - p.right - (p.held - p.kept) : 0, keys,
                                                        p.left_top, p.right_bottom});
        valid = p.kept + n;
        s.cells->enqueue_rekey(ps, valid);
        break;
    case Merge::all:
        // [everything held | arrivals], one sort in the order [left arrivals | held | right arrivals].
        ps.reserve(p.held + n);
        device::copy_particles(dev, s.inbox, 0, ps, p.held, n);
        s.cells->enqueue_sort_with_arrivals(ps, p.held, p.from_left, p.from_right, ps.ranges.first_owned(),
                                            ps.ranges.end_owned(), keys);
        valid = p.kept + n;
        break;
    }
    // The cell count and, with several devices, the column positions: this device's own round
    // trip, waited for on its own thread, which then enqueues the rest of the tables at once.
    const bool several = slabs_.size() > 1;
    cl_rt::EventSet counted;
    for (auto& ev : written.events_of(dev)) counted.add(dev, ev);
    ps.ranges = device::ParticleRanges{0, valid, 0};
    s.cells->enqueue_count_cells(ps, valid, counted);
    if (several) enqueue_column_positions(s, valid, counted);
    counted.wait("sorting particles after the exchange", wait_);
    if (several) {
        const auto& l = s.cells->located();
        ps.ranges = s.empty() || l.size() < 2 ? device::ParticleRanges{0, 0, 0}
                                              : device::ParticleRanges{l.front(), l.back() - l.front(), valid - l.back()};
        remember_columns(s);
    }
    const std::size_t cells = s.cells->finish_tables(ps, ps.ranges.active());
    // The interior's forces stand where its tables held every cell (at most the merged count + 1).
    s.interior_first = s.interior_end = 0;
    if (p.overlap && several && cells + 1 <= s.cells->interior_capacity() && p.run_end > p.run_first) {
        const auto& l = s.cells->located();
        s.interior_first = l[p.interior_lo - s.first_col];
        s.interior_end = l[p.interior_hi - s.first_col];
        if (s.interior_first != p.run_first || s.interior_end != p.run_end)  // the settle's counts
            throw Error("internal: the interior's particles are [" + std::to_string(s.interior_first) + ", " +
                        std::to_string(s.interior_end) + ") after the merge, not [" + std::to_string(p.run_first) +
                        ", " + std::to_string(p.run_end) + ") as the settle counted them, on " + s.device->label());
    }
    then(e);
}

std::pair<std::size_t, std::size_t> Exchange::interior_columns(std::size_t d) const {
    // The owned columns two or more inside the old ones: their rows reach only columns
    // [first_old + 1, end_old - 1), which no arrival enters, and whose kept particles the edge
    // sorts leave in place. Their forces need no arrival (Interior).
    const Slab& s = slabs_[d];
    if (!interior_.allowed || !interior_.allowed(d) || !s.columns_known() || s.columns_end - s.columns_first < 4)
        return {0, 0};
    return {std::max(s.first_col, s.columns_first + 2), std::min(s.end_col, s.columns_end - 2)};
}

device::KeyRange Exchange::interior_keys(std::size_t d) const {
    const auto [lo, hi] = interior_columns(d);
    if (lo >= hi) return {0, 0};
    return {partition_.column_key(lo), partition_.column_key(hi)};
}

void Exchange::send_remote_counts(const std::vector<Block>& blocks) {
    // Every pair of a slab here and a slab of another rank that needs columns: a message each step
    // (count 0 included), so the receiver knows what to wait for without asking.
    const std::size_t D = slabs_.size();
    for (std::size_t d = 0; d < D; ++d) {
        if (!ranks_.here(d)) continue;
        for (std::size_t e = 0; e < D; ++e) {
            if (!remote_pair(d, e)) continue;
            auto& l = remote_send_[{d, e}];
            if (!l) l = ranks_.ranks->sender(*slabs_[d].device, ranks_.slab_rank[e], static_cast<int>(d * D + e));
            const auto b = std::find_if(blocks.begin(), blocks.end(), [&](const Block& x) { return x.d == d && x.e == e; });
            if (b == blocks.end())
                l->send(slabs_[d].outbox, 0, 0);
            else
                l->send(slabs_[d].outbox, b->base, slabs_[d].cells->gather_count(b->index));
        }
    }
}

std::vector<std::size_t> Exchange::remote_arrivals(std::size_t e, bool left) {
    const std::size_t D = slabs_.size();
    std::vector<std::size_t> out;
    for (std::size_t d = 0; d < D; ++d) {
        if ((d < e) != left || !remote_pair(d, e)) continue;
        auto& l = remote_receive_[{d, e}];
        if (!l) l = ranks_.ranks->receiver(*slabs_[e].device, ranks_.slab_rank[d], static_cast<int>(d * D + e));
        out.push_back(l->wait_count());
    }
    return out;
}

void Exchange::enqueue_column_positions(Slab& s, std::size_t n, cl_rt::EventSet& done) const {
    std::vector<std::uint32_t> cols;
    for (std::size_t c = s.first_col; c <= s.end_col && !s.empty(); ++c) cols.push_back(partition_.column_key(c));
    s.cells->enqueue_locate(*s.store, n, cols, done);
}

void Exchange::remember_columns(Slab& s) {
    const auto& at = s.cells->located();
    s.column_at.assign(at.begin(), at.end());
    s.columns_first = s.first_col;
    s.columns_end = s.end_col;
    if (s.empty() || !s.columns_known()) {
        s.column_at.clear();
        s.columns_first = s.columns_end = 0;
    }
}

}  // namespace clsph::multi
