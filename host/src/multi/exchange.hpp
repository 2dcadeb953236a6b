// The exchange between slabs, after the drift: afterwards every device holds [ghosts | owned |
// ghosts] in sorted order, its cell tables are enqueued, and then(d) has run on its host thread.
//
// Particles move less than a column per step (CFL), so what device e needs from device d (d's
// particles now in e's columns) was, before the drift, within one column of them: a window of d's
// still-sorted particles, known from the last exchange's column positions. Per step:
//   1. settle and gather   each device settles its drifted particles into cells (keys in pos.w)
//                          and packs each window's particles that the receiver needs into its
//                          outbox; it also starts sorting the keys of what it keeps
//   2. send                outboxes leave through the Links (transfer queues) while the kept
//                          particles move into sorted order, leaving room below for the arrivals
//                          from the left and above for those from the right
//   3. receive and merge   arrivals land around the kept particles; only the edges, where they
//                          meet, are sorted; then the cell tables
// Every device's sort input is [left arrivals | kept, in their previous order | right arrivals]:
// a subsequence of what one device would sort, so with a stable sort each cell lists its
// particles in the order one device would, and results do not depend on the device count.
// One device is the same path with no windows. A slab too narrow for its edges sorts everything
// it holds with the arrivals (in the same canonical order); a particle that jumped more than a
// column (which the CFL limit rules out) makes every device send from its whole slab instead.
#pragma once
#include "cl/async.hpp"
#include "cl/relay.hpp"
#include "multi/link.hpp"
#include "multi/ranks.hpp"
#include "multi/partition.hpp"
#include "multi/phase_timer.hpp"
#include "multi/slab.hpp"

#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace clsph::multi {

using PerDevice = std::function<void(std::size_t)>;
// Runs work(d) for every device, each on its own host thread where that helps.
using ForEachDevice = std::function<void(const PerDevice&)>;

// Across ranks (clsph/ranks.hpp) every rank holds every slab's columns but only its own slabs'
// devices and particles (Slab::device is null for the others'): each rank runs the exchange for its
// slabs, sends a count (0 included) to every slab of another rank that needs columns, and takes one
// from each such slab, so receivers learn what comes before they plan; the jump check and the
// removed count are summed over the ranks. Arrivals are taken in sender order as in one process,
// so the result does not depend on where the slabs run.
struct RankMap {
    Ranks* ranks = nullptr;     // null: one process
    std::vector<int> slab_rank;  // per slab (empty: all here)
    int rank = 0;
    bool here(std::size_t d) const { return slab_rank.empty() || slab_rank[d] == rank; }
};

class Exchange {
public:
    Exchange(const Partition& partition, std::vector<Slab>& slabs, ForEachDevice for_each_device,
             cl_rt::EventSet::Mode wait, PhaseTotals& phases, bool always_wide = false, RankMap ranks = {});
    // Once, after the first upload: each device sorts what it was given and finds its column
    // positions. Returns the particles removed (outside the domain).
    std::size_t sort_uploaded();
    // One exchange (see above); returns the particles removed (they left the domain). `created`
    // (inlets: scene/open_boundaries.hpp; null or empty: none) are new particles every host made
    // alike: each device takes those in the columns it needs (owned or halo) after its right
    // arrivals, the order one device gives them too ([held | created] sorted stably), so each
    // cell lists them last on any device count.
    // `before` (the step's drift), if given, runs on each device's thread before its settle.
    std::size_t run(const PerDevice& then, const Particles* created = nullptr, const PerDevice& before = {});
    // A step with the last exchange's tables kept (run.list_buffer: multi/list_schedule.hpp): no
    // settle, no sort; each device runs before(d), its ghosts are brought up to date from their
    // owners (the same particles, in the same places, as the last run() left them), then then(d).
    void keep(const PerDevice& then, const PerDevice& before = {});
    // keep() with no host wait (the step ahead on several devices): every device's before(d), the
    // ghosts' copies through `relay` (which orders them on the devices' queues), then(d) — all
    // enqueued from this thread. One device: no copies, `relay` may be null.
    void keep_ahead(cl_rt::Relay* relay, const PerDevice& then, const PerDevice& before);
    // With nothing in flight, before steps ahead: the staging keep_ahead's copies across contexts
    // will use, made (mapping pinned memory waits for the device's queue).
    void prepare_keep_ahead();
    // The halo overlapped with the interior's forces. Where allowed(d) and a device's merge sorts
    // only its edges, the tables of what it kept are built as soon as it has moved them into
    // sorted order, and run(d, first, last) enqueues the force pass of particles [first, last):
    // the owned particles that lie two columns or more inside the device's old columns (their rows
    // hold no arrival), where the settle's counts put them. All of that runs while the device's
    // blocks travel. After the merge, the slab's interior_first and interior_end say whether those
    // results stand (the rest of the owned particles are the force pass's in then(d)); both 0
    // where they do not (the interior's tables overflowed), and the pass is then whole.
    struct Interior {
        std::function<bool(std::size_t)> allowed;
        std::function<void(std::size_t, std::size_t, std::size_t)> run;
    };
    void overlap_interior(Interior interior) { interior_ = std::move(interior); }

private:
    // keep(): owner d's particles [first, first + n) copied over device e's ghosts at `to`.
    struct Refresh { std::size_t d, e, first, n, to; };
    std::vector<Refresh> refreshes() const;
    std::map<std::pair<std::size_t, std::size_t>, std::unique_ptr<cl_rt::PinnedHost>> refresh_staging_;
    struct Block { std::size_t d, e, index, base; };  // sender, receiver, gather block, outbox offset
    enum class Merge { empty, kept_only, edges, all };
    struct Plan {
        Merge merge = Merge::all;
        std::size_t held = 0, kept = 0, from_left = 0, from_right = 0, left = 0, right = 0, end = 0;
        std::uint32_t left_top = 0xffffffffu, right_bottom = 0;  // the edges' bounds (device::EdgeSort)
        bool overlap = false;  // the interior's forces while the arrivals travel (Interior)
        std::size_t interior_lo = 0, interior_hi = 0;  // their columns
        std::size_t run_first = 0, run_end = 0;  // the range run() computes: [lo, hi)'s particles
    };
    void settle_and_gather(bool wide, std::vector<Block>& blocks, std::vector<char>& presorted, const PerDevice& before = {});
    Plan plan(std::size_t e, bool presorted, std::size_t from_left, std::size_t from_right, std::size_t created) const;
    void send(const std::vector<Block>& blocks, const std::vector<Plan>& plans);
    void receive_and_merge(std::size_t e, const std::vector<Block>& blocks, const Plan& p, const PerDevice& then);
    void enqueue_column_positions(Slab& s, std::size_t n, cl_rt::EventSet& done) const;
    static void remember_columns(Slab& s);
    Link& link(std::size_t from, std::size_t to);
    // Device d's interior (Interior), from its cuts and its old columns: its columns [lo, hi) (none
    // where lo >= hi) and their keys ({0, 0}: none).
    std::pair<std::size_t, std::size_t> interior_columns(std::size_t d) const;
    device::KeyRange interior_keys(std::size_t d) const;
    // Counts to and from slabs of other ranks (after the gathers; before the plans).
    void send_remote_counts(const std::vector<Block>& blocks);
    std::vector<std::size_t> remote_arrivals(std::size_t e, bool left);
    bool remote_pair(std::size_t d, std::size_t e) const {
        return d != e && !need_[e].empty() && ranks_.here(d) != ranks_.here(e);
    }

    const Partition& partition_;
    std::vector<Slab>& slabs_;
    ForEachDevice for_each_device_;
    cl_rt::EventSet::Mode wait_;
    PhaseTotals& phases_;
    bool always_wide_;  // tests: the jump path every step
    std::vector<Need> need_;
    const Particles* created_ = nullptr;
    std::vector<std::vector<std::size_t>> created_for_;  // per slab: indices into *created_
    std::map<std::pair<std::size_t, std::size_t>, std::unique_ptr<Link>> links_;
    RankMap ranks_;
    Interior interior_;
    std::map<std::pair<std::size_t, std::size_t>, std::unique_ptr<RemoteSendLink>> remote_send_;
    std::map<std::pair<std::size_t, std::size_t>, std::unique_ptr<RemoteReceiveLink>> remote_receive_;
};

}  // namespace clsph::multi
