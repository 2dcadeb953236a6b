// One device's particles from drifted positions to the neighbour table (stages 1-5 of the step:
// docs/multi_device.md), and the pieces of it that the exchange between slabs takes apart:
//   cells.keys / cells.settle    offsets settled into cells, a key per particle (invalid outside
//                                the domain or outside the columns this device keeps)
//   cells.drift_keys             the step ahead: the first kick and drift, settle and keys at once
//   sort                         radix sort of (key, index) on the grid's key bits only
//   reorder.*                    every particle array into sorted order through the one scratch
//   [cells.flag] / scan / scatter  compaction: cell_key[K], cell_start[K+1] (the flags counted by
//                                the scan itself unless unfused)
//   cells.ranges                 each cell's 9 neighbour rows as particle ranges
//   exchange.flag / gather       the particles of a window whose key lies in a range, packed
//   edge.* / cells.arrival_keys  the sorts that merge arrivals with the particles kept
// After the tables, vals holds each particle's cell index (the fine-grained neighbour loop reads it).
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/primitives.hpp"

#include "clsph/interaction.hpp"

#include <array>
#include <string>
#include <vector>

namespace clsph::device {

struct CellPassResult {
    std::size_t cells = 0;    // non-empty cells
    std::size_t active = 0;   // particles left
    std::size_t removed = 0;  // particles that were outside the domain, now removed
};

// Keys [lo, hi): the columns a device needs are one such range (the split axis is the key's most
// significant part).
struct KeyRange {
    std::uint32_t lo = 0, hi = 0;
};

// Which of particles [0, n) a sort keeps (the others get the invalid key and sort last): those of
// [keep_first, keep_end) whose key lies in `keys`, and every one from tail_first on. With `settle`
// the offsets are settled into their cells first (else pos.w already holds the key).
struct SortSelection {
    std::size_t n = 0, keep_first = 0, keep_end = 0, tail_first = 0;
    KeyRange keys;
    bool settle = false;
};

// The two edges of an almost sorted array, each sorted on its own: [0, left) and [right, end), of
// which [drop_first, drop_end) and keys outside `keys` are dropped; valid_right of the right edge
// stay, which leaves [0, right + valid_right) sorted. An empty edge (left 0, right == end) is
// skipped. The bounds let each sort run over the few key bits that vary in its edge: the left
// edge's entries with keys from left_top up, and the right edge's with keys below right_bottom,
// must be particles in sorted order (the kept ones) that come after, resp. before, every other
// entry of the edge; those keys then sort as left_top, resp. right_bottom. The defaults bound nothing.
struct EdgeSort {
    std::size_t left = 0, right = 0, end = 0, drop_first = 0, drop_end = 0, valid_right = 0;
    KeyRange keys;
    std::uint32_t left_top = 0xffffffffu, right_bottom = 0;
};

// What settling the owned particles found (enqueue_settle, read when its events are waited for).
struct Settled {
    std::size_t left_domain = 0;  // now outside the domain (removed)
    std::size_t jumped = 0;       // moved more than one column in the step
    std::size_t kept = 0;         // now in the key range this device keeps
    std::size_t kept_below_lo = 0, kept_below_hi = 0;  // of those, with keys below the split's lo, hi
};

// The step ahead's first kick and drift (Physics): its dt (the clock's float), rho0 and the halt flag.
struct Drift {
    const cl_rt::Buffer& dt;
    float rho0;
    const cl_rt::Buffer& halt;
};

class CellPipeline {
public:
    // fused: stages that read what the one before wrote, element for element, share a launch
    // (issue 30); off (Seams::unfused): a launch each, as before, for the tests that both agree.
    CellPipeline(cl_rt::Device& device, const Grid& grid, bool fused = true);
    // One device on its own: settle, sort, drop particles outside the domain, build the tables.
    CellPassResult run(ParticleStore& store);

    // Settles and sorts every particle of [0, n), keeping [keep_first, keep_end); returns, for each
    // threshold key, the first sorted position whose key is >= it (one blocking read).
    std::vector<std::size_t> sort_particles(ParticleStore& store, std::size_t n, std::size_t keep_first,
                                            std::size_t keep_end, const std::vector<std::uint32_t>& thresholds);
    // The keys of a selection and their sort; then moving every array into that order at dst_offset
    // (what lies below is left alone: room for arrivals from the left).
    void enqueue_sort_keys(ParticleStore& store, const SortSelection& selection);
    void enqueue_reorder(ParticleStore& store, std::size_t n, std::size_t dst_offset);
    // The step ahead on one device, in one launch and the sort: the first kick and drift of the
    // owned particles (Physics::kick_drift_on_clock), enqueue_settle_on_device and the keys of
    // enqueue_sort_keys over the active particles, keeping the owned ones in `keep`. Bitwise those
    // three; not with moving solids (they are put between the drift and the settle).
    void enqueue_drift_sort_keys(ParticleStore& store, KeyRange keep, const Drift& drift);
    // Both, at offset 0.
    void enqueue_sort(ParticleStore& store, const SortSelection& selection);

    // Settles the owned particles' drifted offsets into cells (keys in pos.w, nothing moved) and
    // counts what settled() reports.
    // With `split`, also the kept particles whose keys lie below split.lo and below split.hi: where
    // those keys begin among them once sorted (the interior of the halo overlap: multi/exchange.cpp).
    void enqueue_settle(ParticleStore& store, KeyRange keep, cl_rt::EventSet& done, KeyRange split = {0, 0});
    Settled settled() const;
    // The step ahead: the same settle with its counters left on the device (end_step reads and
    // resets them: kernels/step_clock.cl).
    void enqueue_settle_on_device(ParticleStore& store, KeyRange keep);
    // For each block (a receiving device): the particles of the window [first, end) whose key lies
    // in `keys`, in order, into `out` at `base`; their count is read into gather_count(block).
    void begin_gathers(std::size_t blocks);
    void enqueue_gather(ParticleStore& store, std::size_t first, std::size_t end, KeyRange keys, ParticleArrays& out,
                        std::size_t base, std::size_t block, cl_rt::EventSet& done);
    std::size_t gather_count(std::size_t block) const { return block < gather_counts_.size() ? gather_counts_[block] : 0; }

    // Merging arrivals with the particles kept. Edges (see EdgeSort), then the keys rebuilt from
    // pos.w for the tables; or, where the edges cannot be sorted alone (a narrow slab), everything:
    // the particles held [0, held) and the arrivals unpacked after them (`left` ones, then `right`
    // ones), taken as [left arrivals | held | right arrivals] — the order one device would hold
    // them in — into [0, kept + left + right).
    void enqueue_edge_sort(ParticleStore& store, const EdgeSort& edges);
    void enqueue_rekey(ParticleStore& store, std::size_t n);
    void enqueue_sort_with_arrivals(ParticleStore& store, std::size_t held, std::size_t left, std::size_t right,
                                    std::size_t keep_first, std::size_t keep_end, KeyRange keys);
    // Edge sorts through buffers of their own (the edges' size), not the store's reorder scratch:
    // where the interior's forces run while the arrivals travel (they sit in the scratch then).
    void set_edges_apart(bool apart) { edges_apart_ = apart; }
    bool edges_apart() const { return edges_apart_; }
    // Bytes of the arrays an edge sort of m particles goes through (four side by side).
    static std::size_t edge_scratch_bytes(std::size_t m) { return m * ParticleArrays::kBytesPerParticle; }

    std::vector<std::size_t> locate(ParticleStore& store, std::size_t n, const std::vector<std::uint32_t>& thresholds);
    // locate() without blocking: the positions are read into located() once `done` is waited for.
    void enqueue_locate(ParticleStore& store, std::size_t n, const std::vector<std::uint32_t>& thresholds,
                        cl_rt::EventSet& done);
    const cl_rt::PinnedArray<std::uint32_t>& located() const { return located_host_; }
    // Cell tables over the sorted, valid particles [0, n); returns the number of non-empty cells.
    std::size_t build_tables(ParticleStore& store, std::size_t n);
    // build_tables in two halves: the flags and their scan with a read of the cell count into
    // `done`; after the wait, finish_tables enqueues the rest.
    void enqueue_count_cells(ParticleStore& store, std::size_t n, cl_rt::EventSet& done);
    std::size_t finish_tables(ParticleStore& store, std::size_t n);
    // Several devices, while the arrivals travel (the halo overlapped with the interior's forces):
    // enqueue_tables_bounded over [0, n) where [0, hole) waits for the left arrivals and [hole, n)
    // holds the kept particles in their final places; nothing comes back. The cells of columns
    // [first_old + 1, end_old - 1) then hold their final particles (arrivals land only outside
    // them), so the rows of cells in [first_old + 2, end_old - 2) are the ones the merged tables
    // will have, provided the count fitted: it is at most the merged tables' count + 1 (the hole's
    // cell), so a merged count k with k + 1 <= interior_capacity() says it did.
    // Arrival order and edges apart only (throws otherwise: the morton order moves particles within
    // cells, and an edge sort through the scratch would overwrite the interior's forces).
    void enqueue_interior_tables(ParticleStore& store, std::size_t n, std::size_t hole);
    std::size_t interior_capacity() const { return interior_capacity_; }
    // The step ahead: the tables without the count coming back. Every launch over cells runs over
    // the tables' capacity; the count lands in cell_count() ([0]: what the tables hold, [1]: as
    // found); a count above the capacity sets HALT_CELLS in `halt` (kernels/step_clock.cl) and
    // the host grows the tables (grow_cells) and redoes the step.
    void enqueue_tables_bounded(ParticleStore& store, std::size_t n, const cl_rt::Buffer& halt);
    const cl_rt::Buffer& cell_count() const { return cell_count_; }
    std::size_t cell_capacity() const { return cell_capacity_; }
    // Room for k cells (with the headroom); the next bounded tables launch over it.
    void grow_cells(std::size_t k) { reserve_cells(k); }
    // The count as the host learnt it (the step ahead): probes read the tables with it.
    void set_counted_cells(std::size_t k) { cells_ = std::min(k, cell_capacity_); }
    // Tables the host counted (built synchronously), kept by steps ahead: their count put where
    // the kernels that read it on the device (the probes in the queue, end_step's record) find it.
    void store_count();
    // The order within cells (clsph/interaction.hpp; never automatic): with morton every build of
    // the tables first sorts each cell's particles along the sub-cell Morton curve (order_within_cells),
    // moving every array once more (kernels/cell_order.cl, built by set_order); arrival (the
    // default) leaves them in the sort's order.
    void set_order(CellOrder order);
    CellOrder order() const { return order_; }
    // What order_within_cells scales the offsets by along s, a, b: 4 sub-cells per cell edge (two
    // levels of the Morton curve: 64 sub-cells), in float as the kernel takes them.
    static std::array<float, 3> sub_cell_scales(const GridParams& g) {
        return {4.0f / g.cell_s, 4.0f / g.cell_a, 4.0f / g.cell_b};
    }
    // Spare cell capacity kept when the tables grow (Options::cell_headroom).
    void set_cell_headroom(double h) { cell_headroom_ = h; }
    const cl_rt::Buffer& settle_counters() const { return counters_; }

    std::size_t cells() const { return cells_; }
    // Whether the count of non-empty cells is only on the device (cell_count()[0]: the step ahead's
    // bounded tables), cells() then being the tables' capacity.
    bool counted_on_device() const { return counted_on_device_; }
    const cl_rt::Buffer& cell_key() const { return cell_key_; }
    const cl_rt::Buffer& cell_start() const { return cell_start_; }
    const cl_rt::Buffer& ranges() const { return ranges_; }
    // Device bytes of the cell tables (they follow the number of non-empty cells, not the domain).
    std::size_t table_bytes() const { return cell_key_.bytes() + cell_start_.bytes() + ranges_.bytes(); }
    // Room in the tables for k cells and the headroom (the builds grow them as they need; the
    // bounded ones cannot, and hold what the last builds made room for).
    void reserve_cells(std::size_t k);

private:
    void ensure_counters();
    // Builds drift_histogram.cl's kernel the first time; whether it runs in the sort's work-groups.
    bool drift_histogram_usable();
    bool drift_histogram_checked_ = false;
    // The compaction's scan over the sorted keys of [0, n) into vals (n + 1 entries).
    void scan_cell_starts(ParticleStore& ps, std::size_t n);
    // With CellOrder::morton: each cell's particles of the sorted [0, n) into their Morton order, the
    // order through vals (free until the scan writes it); the keys stay as they are.
    void order_within_cells(ParticleStore& ps, std::size_t n);
    // Every particle array gathered through `order` into [dst_offset, dst_offset + n).
    void gather_arrays(ParticleStore& ps, std::size_t n, std::size_t dst_offset, const cl_rt::Buffer& order,
                       const std::string& name);
    CellOrder order_ = CellOrder::arrival;
    // Sorts n (key, value) pairs on their lowest `bits` bits (0: the grid's key bits), ping-ponging
    // through the store's reorder scratch.
    void sort_pairs(RadixSort& sorter, cl_rt::Buffer& keys, cl_rt::Buffer& vals, std::size_t n, ParticleStore& ps,
                    unsigned bits = 0);
    // One edge of enqueue_edge_sort: particles [first, first + count) by their keys clamped to
    // [code_lo, code_hi], the first `kept` back into place from `first`.
    void sort_edge(ParticleStore& ps, std::size_t first, std::size_t count, std::size_t kept, const EdgeSort& e,
                   std::uint32_t code_lo, std::uint32_t code_hi);
    cl_rt::Device& device_;
    const Grid& grid_;
    bool fused_;
    RadixSort sort_, edge_sort_;
    Scan scan_;
    std::size_t wg_;
    cl::Kernel keys_k_, gather4_k_, gather1_k_, flag_k_, scatter_k_, ranges_k_, locate_k_;
    cl::Kernel tables_bounded_k_, ranges_bounded_k_, within_k_, codes_k_;
    cl_rt::Buffer cell_count_;
    bool counted_on_device_ = false;
    double cell_headroom_ = 0.25;
    cl::Kernel settle_k_, flag_range_k_, gather_range_k_, edge_keys_k_, edge_gather_k_, edge_place_k_, arrival_keys_k_;
    cl::Kernel drift_keys_k_, drift_histogram_k_;  // the latter built on first use
    cl_rt::Buffer counters_, flags_, edge_keys_, edge_vals_;
    cl_rt::Buffer edge_arrays_;  // edges apart: the edges' particles in sorted order, before they go back
    bool edges_apart_ = false;
    cl_rt::Buffer interior_halt_;  // the interior's tables: their overflow flag (read by nothing)
    std::size_t interior_capacity_ = 0;
    cl_rt::Buffer cell_key_, cell_start_, ranges_, thresholds_, located_;
    std::size_t cell_capacity_ = 0, cells_ = 0;
    // The host ends of the small transfers the host waits for, in pinned memory (cl/async.hpp).
    cl_rt::PinnedArray<std::uint32_t> counters_host_, gather_counts_, thresholds_host_, located_host_, cell_count_host_;
};

}  // namespace clsph::device
