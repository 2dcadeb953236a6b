// One device's step pipeline up to the neighbour table (DESIGN.md "One device", stages 1-5):
//   cells.keys     settle offsets into cells, key per particle (invalid outside the domain)
//   sort           radix sort of (key, index) on the grid's key bits only
//   reorder.*      every particle array into sorted order through the one scratch buffer
//                  (positions, velocity+density, acceleration+drho/dt, ids)
//   cells.flag / cells.scan / cells.scatter   compaction: cell_key[K], cell_start[K+1]
//   cells.ranges   each cell's 9 neighbour rows as particle ranges
// After run(), particles outside the domain are gone (counted), and vals holds each particle's
// cell index (the fine-grained neighbour loop reads it).
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/primitives.hpp"

#include <array>
#include <vector>

namespace clsph::device {

struct CellPassResult {
    std::size_t cells = 0;    // non-empty cells
    std::size_t active = 0;   // particles left
    std::size_t removed = 0;  // particles that were outside the domain, now removed
};

class CellPipeline {
public:
    CellPipeline(cl_rt::Device& device, const Grid& grid);
    // One device on its own: sort, drop particles outside the domain, build the tables.
    CellPassResult run(ParticleStore& store);

    // The two halves, for several devices (host/src/multi/):
    // keys for particles [0, n) — those outside [keep_first, keep_end) get the invalid key, so the
    // sort drops them — then sort and reorder every array. Returns, for each threshold key, the
    // first sorted position whose key is >= it (one blocking read).
    std::vector<std::size_t> sort_particles(ParticleStore& store, std::size_t n, std::size_t keep_first,
                                            std::size_t keep_end, const std::vector<std::uint32_t>& thresholds);
    // sort_particles in two halves: enqueue the keys, sort and reorder; then (blocking) locate.
    void enqueue_sort(ParticleStore& store, std::size_t n, std::size_t keep_first, std::size_t keep_end);
    // As above, and particles from tail_first on are always kept, while those of [keep_first,
    // keep_end) are kept only if their key lies in [key_lo, key_hi) (the columns a device needs).
    // The sorted particles land at [dst_offset, dst_offset + n) (what is below is left alone: room
    // for particles that arrive from a neighbour while this sort runs).
    void enqueue_sort(ParticleStore& store, std::size_t n, std::size_t keep_first, std::size_t keep_end,
                      std::size_t tail_first, std::uint32_t key_lo, std::uint32_t key_hi, bool settle,
                      std::size_t dst_offset = 0);
    // enqueue_sort in two halves: the keys and their sort (which need no offset), then moving every
    // array into that order at dst_offset.
    void enqueue_sort_keys(ParticleStore& store, std::size_t n, std::size_t keep_first, std::size_t keep_end,
                           std::size_t tail_first, std::uint32_t key_lo, std::uint32_t key_hi, bool settle);
    void enqueue_reorder(ParticleStore& store, std::size_t n, std::size_t dst_offset);

    // The exchange overlapped with the sort (host/src/multi/): arrivals are written into the inbox
    // (on the transfer queue, while the kept particles sort), then copied to their places around
    // the sorted ones; the edges [0, left) and [right, end) are then sorted on their own (entries
    // in [drop_first, drop_end), which the sort before dropped, and keys outside [key_lo, key_hi)
    // are dropped; valid_right must be how many of the right edge stay), which leaves
    // [0, right + valid_right) sorted; then the keys are rebuilt from pos.w for the tables.
    void begin_inbox(std::size_t particles);
    cl_rt::Buffer inbox_pos, inbox_velrho, inbox_accel, inbox_id;
    void enqueue_unpack_inbox(ParticleStore& store, std::size_t from, std::size_t count, std::size_t to);
    void enqueue_edge_sort(ParticleStore& store, std::size_t left, std::size_t right, std::size_t end,
                           std::size_t drop_first, std::size_t drop_end, std::uint32_t key_lo, std::uint32_t key_hi,
                           std::size_t valid_right);
    void enqueue_rekey(ParticleStore& store, std::size_t n);
    // Where the edges cannot be sorted alone: the particles held [0, held) (only those of
    // [keep_first, keep_end) with a key in [key_lo, key_hi) stay) and the arrivals unpacked after
    // them (`left` then `right`), sorted as [left arrivals | held | right arrivals] (the canonical
    // order: what one device would have) into [0, kept + left + right).
    void enqueue_sort_with_arrivals(ParticleStore& store, std::size_t held, std::size_t left, std::size_t right,
                                    std::size_t keep_first, std::size_t keep_end, std::uint32_t key_lo,
                                    std::uint32_t key_hi);
    // Bytes of the reorder scratch an edge sort of m particles uses (four arrays side by side).
    static std::size_t edge_scratch_bytes(std::size_t m) { return m * (3 * 4 * sizeof(float) + sizeof(std::uint32_t)); }

    // The exchange with one sort per step (host/src/multi/): settle the drifted owned particles into
    // cells (keys in pos.w, nothing moved), reading back how many left the domain, how many moved
    // more than one column and how many now have a key in [key_lo, key_hi) (settled()).
    void enqueue_settle(ParticleStore& store, std::uint32_t key_lo, std::uint32_t key_hi, cl_rt::EventSet& done);
    std::array<std::uint32_t, 3> settled() const { return {counters_host_[0], counters_host_[1], counters_host_[2]}; }
    // Gathers, for each receiving device, the particles of a window [first, end) whose key lies in
    // [key_lo, key_hi) into the outbox buffers at `base`, in order; their count is read into
    // gather_count(block). begin_gathers sizes the outbox and the counts first.
    void begin_gathers(std::size_t blocks, std::size_t particles);
    void enqueue_gather(ParticleStore& store, std::size_t first, std::size_t end, std::uint32_t key_lo,
                        std::uint32_t key_hi, std::size_t base, std::size_t block, cl_rt::EventSet& done);
    std::size_t gather_count(std::size_t block) const { return block < gather_counts_.size() ? gather_counts_[block] : 0; }
    cl_rt::Buffer outbox_pos, outbox_velrho, outbox_accel, outbox_id;
    std::vector<std::size_t> locate(ParticleStore& store, std::size_t n, const std::vector<std::uint32_t>& thresholds);
    // locate() without blocking: the positions are read into located() once `done` is waited for.
    void enqueue_locate(ParticleStore& store, std::size_t n, const std::vector<std::uint32_t>& thresholds,
                        cl_rt::EventSet& done);
    const cl_rt::PinnedArray<std::uint32_t>& located() const { return located_host_; }
    // Cell tables over the sorted, valid particles [0, n); returns the number of non-empty cells.
    std::size_t build_tables(ParticleStore& store, std::size_t n);
    // build_tables in two halves, for several devices at once: enqueue the flags and their scan with
    // a read of the cell count into `done`; after the wait, finish_tables enqueues the rest.
    void enqueue_count_cells(ParticleStore& store, std::size_t n, cl_rt::EventSet& done);
    std::size_t finish_tables(ParticleStore& store, std::size_t n);
    // Gives particles [first, end) the invalid key (they were handed to another device).
    void mark_invalid(ParticleStore& store, std::size_t first, std::size_t end);

    std::size_t cells() const { return cells_; }
    const cl_rt::Buffer& cell_key() const { return cell_key_; }
    const cl_rt::Buffer& cell_start() const { return cell_start_; }
    const cl_rt::Buffer& ranges() const { return ranges_; }
    // Device bytes of the cell tables (they follow the number of non-empty cells, not the domain).
    std::size_t table_bytes() const { return cell_key_.bytes() + cell_start_.bytes() + ranges_.bytes(); }

private:
    void reserve_cells(std::size_t k);
    cl_rt::Device& device_;
    const Grid& grid_;
    RadixSort sort_, edge_sort_;
    Scan scan_;
    std::size_t wg_;
    cl::Kernel settle_k_, flag_range_k_, gather_range_k_;
    cl_rt::Buffer counters_, flags_;
    // The host ends of the small transfers the host waits for, in pinned memory (cl/async.hpp).
    cl_rt::PinnedArray<std::uint32_t> counters_host_, gather_counts_;
    std::size_t outbox_capacity_ = 0, inbox_capacity_ = 0;
    cl::Kernel edge_keys_k_, edge_gather_k_, edge_place_k_, arrival_keys_k_;
    cl_rt::Buffer edge_keys_, edge_vals_;
    cl::Kernel keys_k_, gather4_k_, gather1_k_, flag_k_, scatter_k_, cell_of_k_, ranges_k_, locate_k_, invalid_k_;
    cl_rt::Buffer cell_key_, cell_start_, ranges_, thresholds_, located_;
    std::size_t cell_capacity_ = 0, cells_ = 0;
    cl_rt::PinnedArray<std::uint32_t> thresholds_host_, located_host_, cell_count_host_;
};

}  // namespace clsph::device
