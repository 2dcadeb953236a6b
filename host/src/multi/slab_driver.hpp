// One simulation over several devices (DESIGN.md "Many devices"): the domain is cut into slabs of
// cell columns along the split axis, one per device; each device holds [ghosts | owned | ghosts]
// in sorted order. Before the first step each device is timed on samples of the scene (the
// balancer's calibration, so unequal devices do not start from an equal split). Per step: kick and
// drift on every device; the balancer moves the cuts from the last step's force times; each
// device settles its particles into cells and compacts, for every other device, what that device
// now needs (its owned columns and one halo column either side) out of a window of its
// still-sorted particles; the blocks go through pinned host memory (staging works across contexts
// and vendors) on each device's transfer queue while its compute queue sorts the particles it
// keeps, leaving room below and above for the arrivals; once they are in, only the two edges
// where arrivals and kept particles meet are sorted, which leaves [ghosts | owned | ghosts] in
// order; cell tables; forces; second kick. Each phase's commands are enqueued by one host thread
// per device. The first step (and any step where a
// particle jumped more than a column, which the CFL limit rules out) sorts, exchanges ranges and
// sorts again instead. With one device, or one busy device and the others idle, no exchange.
#pragma once
#include "balance/balance_log.hpp"
#include "balance/balancer.hpp"
#include "cl/device.hpp"
#include "clsph/scene.hpp"
#include "device/cell_pipeline.hpp"
#include "device/grid.hpp"
#include "device/particle_store.hpp"
#include "device/physics.hpp"
#include "multi/device_threads.hpp"

#include <fstream>
#include <map>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace clsph::multi {

struct DriverOptions {
    Interaction interaction = Interaction::automatic;
    std::string balance = "dynamic";  // dynamic | static | off
    std::string balance_log;          // CSV path, empty: none
    std::vector<int> slowdown;        // tests: repeat device d's force pass slowdown[d] times
    bool serialize = false;           // tests: one device's force pass at a time
    double headroom = 0.25;
    // How the host waits for the devices (cl/async.hpp); callbacks become polling where they are late.
    cl_rt::EventSet::Mode wait_mode = cl_rt::EventSet::Mode::callbacks;
    // overlap: the kept particles sort while arrivals travel, then the edges; window: one sort per
    // step once the arrivals are in; sort: sort, exchange, sort again.
    std::string exchange = "overlap";
    std::function<std::vector<std::size_t>(std::uint64_t, std::size_t)> cut_schedule;  // tests
    std::uint64_t fail_at_step = 0;  // tests: simulated device failure (clsph/simulation.hpp)
    std::size_t fail_device = 0;
};

struct Slab {
    cl_rt::Device* device = nullptr;
    std::unique_ptr<device::ParticleStore> store;
    std::unique_ptr<device::CellPipeline> cells;
    std::unique_ptr<device::Physics> physics;
    std::size_t first_col = 0, end_col = 0;  // owned columns [first_col, end_col)
    double force_seconds = 0;                // last step's force pass time (the balancer's input)
    double force_total_seen = 0;             // the profiler's force total when force_seconds was taken
    std::size_t received_bytes = 0;         // copied in from other devices since the start
    // Where each owned column [columns_first, columns_end] began in the sorted array after the last
    // exchange: the next step's windows (and the balancer's column profile).
    std::vector<std::uint32_t> column_at;
    std::size_t columns_first = 0, columns_end = 0;
    // The calibration before the first step (several devices, dynamic balance): force pass time =
    // fixed + per_unit * work, and the scene's whole work (so per_unit * work_total is the time
    // this device would take for everything).
    struct Calibration { double fixed = 0, per_unit = 0, work_total = 0; } calibration;
    bool empty() const { return first_col >= end_col; }
};

struct StepOutcome {
    device::KickResult kick;   // over all devices (bad_index: see bad_slab)
    std::size_t bad_slab = 0;
    std::size_t removed = 0;
};

class SlabDriver {
public:
    SlabDriver(const std::vector<cl_rt::Device*>& devices, const device::Grid& grid, const Scene& scene,
               const Particles& particles, const DriverOptions& options);

    StepOutcome start();                 // first cell pass, forces and a zero kick
    StepOutcome step(double dt);
    Particles download();                // owned particles of every device
    std::vector<std::array<float, 2>> probe(const std::vector<std::array<double, 3>>& points);

    const SphParams& params() const { return slabs_.front().physics->params(); }
    std::vector<Slab>& slabs() { return slabs_; }
    std::vector<std::size_t> cuts() const;
    std::size_t owned() const;
    std::size_t columns() const { return grid_.params().n_s; }
    // Particles (ghosts included) and bytes copied between devices in the last step.
    std::size_t moved_particles() const { return moved_; }
    std::size_t moved_bytes() const { return moved_bytes_; }
    // Host wall time spent in each phase of the step since the start (where the time goes).
    const std::map<std::string, double>& phase_seconds() const { return phases_; }

private:
    std::uint32_t column_key(std::size_t column) const;
    std::size_t owner_of(std::uint32_t key) const;
    struct Need { std::size_t lo = 0, first = 0, end = 0, hi = 0; };
    std::vector<Need> needs() const;
    // Exchange, sort, tables, then `then(d)` for every device (on its own host thread where there
    // are several, as soon as its tables are enqueued); returns the particles removed.
    using PerDevice = std::function<void(std::size_t)>;
    std::size_t redistribute(const PerDevice& then);
    std::size_t redistribute_sorted();   // sort, exchange ranges, sort again (first step, fallback)
    std::optional<std::size_t> redistribute_windowed(const PerDevice& then);  // nullopt: fall back
    void remember_columns(Slab& s);
    struct BlockBuffers { cl_rt::Buffer &pos, &velrho, &accel, &id; };
    void read_block(std::size_t sender, const BlockBuffers& src, std::size_t from, std::size_t m, unsigned char* base,
                    std::size_t receiver, cl_rt::EventSet& done, cl_rt::Device::On on = cl_rt::Device::On::compute);
    void write_block(cl_rt::Device& device, const BlockBuffers& dst, const unsigned char* base, std::size_t m,
                     std::size_t to, cl_rt::EventSet& done, cl_rt::Device::On on = cl_rt::Device::On::compute);
    void enqueue_column_positions(Slab& s, std::size_t n, cl_rt::EventSet& done);
    void enqueue_forces_and_kick(std::size_t d, double dt, cl_rt::EventSet& done);
    StepOutcome finish_kick(cl_rt::EventSet& done);  // waits, then the reductions over all devices
    void for_each_device(const std::function<void(std::size_t)>& work);  // one host thread per device
    void rebalance(std::uint64_t step);
    void calibrate(const Particles& p, const std::vector<std::uint32_t>& key, const balance::ColumnProfile& profile);
    balance::ColumnProfile column_profile();

    const device::Grid& grid_;
    DriverOptions options_;
    std::vector<Slab> slabs_;
    std::unique_ptr<balance::Balancer> balancer_;
    std::unique_ptr<std::ofstream> log_file_;
    std::unique_ptr<balance::BalanceLog> log_;
    std::uint64_t steps_ = 0;
    bool rebalance_due_ = false;
    bool windowed_ready_ = false;   // every slab's column positions are known
    std::size_t fallbacks_ = 0;     // windowed steps that had to sort first  // the balancer runs at the next step's first sort
    std::size_t moved_ = 0, moved_bytes_ = 0;
    std::mutex counts_mutex_;  // moved_, moved_bytes_ and received_bytes, from the device threads
    // Per device: pinned host memory that particles going between devices are staged in
    // (pos, velrho, accel: 16 bytes each; id: 4).
    static constexpr std::size_t kStagedBytesPerParticle = 52;
    std::vector<std::unique_ptr<cl_rt::PinnedHost>> staging_;
    std::map<std::string, double> phases_;
    std::unique_ptr<DeviceThreads> threads_;        // several devices: started at the first use
    std::vector<std::size_t> boundary_per_column_;  // boundary particles never move: counted once
};

}  // namespace clsph::multi
