// The interaction pass alone, every form side by side: SPHERIC-2 at t = 0 (bench/spheric2_scene.hpp)
// on one device at a time, the force kernel of each form (clsph/interaction.hpp) timed by its
// launch events (median of repeats after warm-up), checked against the fine form, and what a warp
// executes: candidates, hits, the fine scheme's pair slots (candidate steps with a hit in some lane
// of 32) and a masked scheme's (per batch of 32 steps, the busiest lane's hits), from
// kernels/interaction_stats.cl; and the loop with no pair terms (distances only). With the clusters
// form among them: its list build alone, its candidates and a warp's candidate steps
// (kernels/clusters.cl cluster_counts).
#include "spheric2_scene.hpp"

#include "bench_util.hpp"
#include "clsph/checkpoint.hpp"
#include "clsph/simulation.hpp"
#include "cl/kernel_args.hpp"
#include "device/cell_pipeline.hpp"
#include "device/cluster_list.hpp"
#include "device/sizing.hpp"
#include "device/physics.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

using namespace clsph;

namespace {

struct Loop {
    cl::Kernel kernel;
    bool per_cell = false;
};

void set_loop_args(cl::Kernel& k, const device::ParticleStore& ps, const device::CellPipeline& cp,
                   const device::Grid& grid, float support2) {
    k.setArg(0, cl_uint(ps.ranges.first_owned()));
    k.setArg(1, cl_uint(ps.ranges.end_owned()));
    k.setArg(2, grid.params());
    k.setArg(3, support2);
    k.setArg(4, ps.pos.get());
    k.setArg(5, ps.vals.get());
    k.setArg(6, cp.ranges().get());
}

// The clusters form: what building its lists costs, and what its pass executes against fine
// (kernels/clusters.cl cluster_counts).
void cluster_counts(cl_rt::Device& d, device::ParticleStore& ps, const device::CellPipeline& cp,
                    const device::Grid& grid, float support2, float list2, int warmup, int repeats,
                    double fine_candidates) {
    device::ClusterList list(d, grid, list2);
    const auto s = bench::measure(warmup, repeats, [&] { return bench::time_launches(d, [&] { list.build(ps, cp); }); });
    const std::size_t n = ps.ranges.owned;
    auto k = d.kernel("clusters.cl", "cluster_counts", grid.kernel_options() + list.kernel_options());
    const std::size_t groups = (n + 31) / 32;
    auto counts = d.alloc(groups * 4 * sizeof(cl_uint), "cluster counts");
    cl_rt::set_args(k, ps.ranges.first_owned(), ps.ranges.end_owned(), grid.params(), support2, ps.pos, ps.vals,
                    cp.ranges(), cp.cell_start(), list.begins(), list.masks(), counts);
    d.launch("stats.cluster_counts", k, groups * 32, 32);
    std::vector<cl_uint> c(groups * 4);
    d.read(counts, c.data(), c.size());
    double candidates = 0, hits = 0, steps = 0, fine_steps = 0;
    for (std::size_t g = 0; g < groups; ++g) {
        candidates += c[4 * g];
        hits += c[4 * g + 1];
        steps += c[4 * g + 2];
        fine_steps += c[4 * g + 3];
    }
    std::printf("\nclusters of %zu: list build %.3f ms (%.3f-%.3f; included in the form's time above), %zu cluster "
                "indices (%.1f bytes a particle of lists); per particle %.0f candidates, %.0f within the support (hit "
                "rate %.1f %%); a warp of 32 runs %.2f candidate steps per candidate of its lanes (fine: %.2f, %.0f "
                "candidates a particle)\n",
                device::sizing::kClusterSize, 1e3 * s.median, 1e3 * s.min, 1e3 * s.max, list.capacity(),
                double(device::sizing::cluster_begin_bytes(list.capacity()) +
                       (device::sizing::cluster_boxes_borrowed(list.capacity(), ps.scratch.bytes())
                            ? 0
                            : device::sizing::cluster_box_bytes(list.capacity())) +
                       device::sizing::cluster_mask_bytes(list.capacity(), grid.rows(), grid.reach())) /
                    double(n),
                candidates / double(n), hits / double(n), 100 * hits / candidates, 32 * steps / candidates,
                32 * fine_steps / std::max(1.0, fine_candidates), fine_candidates / double(n));
}

// The particles in another order, which the upload's stable sort keeps within each cell: by id
// (the lattice's order), or by cell and then a Morton code of the offset within the cell (two
// bits per axis: octants, then octants of those).
Particles reordered(const Particles& p, const std::string& how, const Scene& scene) {
    std::vector<std::size_t> order(p.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    if (how == "id") {
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
    } else {
        const device::Grid grid(device::Box{scene.domain.min, scene.domain.max}, scene.physics.support(),
                                scene.domain.split_axis, scene.domain.periodic, 1);
        const auto cell = grid.cell_size_xyz();
        std::vector<std::uint64_t> code(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            std::array<float, 3> off{};
            const std::uint64_t key = grid.locate(p.position[i], off);
            std::uint32_t m = 0;
            for (int level = 0; level < 2; ++level)
                for (int k = 0; k < 3; ++k) {
                    const int axis = grid.axis(k);
                    const double u = std::clamp(off[axis] / cell[axis] + 0.5, 0.0, 0.999999);
                    const auto q = static_cast<std::uint32_t>(u * 4);  // 0..3
                    m = (m << 1) | ((q >> (1 - level)) & 1u);
                }
            code[i] = (key << 6) | m;
        }
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
    }
    Particles q;
    for (std::size_t i : order) q.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    return q;
}

void run_device(cl_rt::Device& d, const Scene& scene, const Particles& p, double t, const std::vector<Interaction>& forms,
                int warmup, int repeats, int reach, CellOrder order) {
    // run.list_buffer (--list-buffer): cells and cluster lists that much wider, as kept tables have them.
    const double list_reach = scene.physics.support() * (1.0 + scene.run.list_buffer);
    device::Grid grid(device::Box{scene.domain.min, scene.domain.max}, list_reach, scene.domain.split_axis,
                      scene.domain.periodic, reach);
    device::ParticleStore ps(d, grid, p.size(), 0.0);
    ps.upload(p);
    device::CellPipeline cp(d, grid);
    cp.set_order(order);
    cp.run(ps);
    const std::size_t n = ps.ranges.owned;
    const float support2 = static_cast<float>(scene.physics.support() * scene.physics.support());
    auto out = d.alloc(4 * n * sizeof(float), "bench accelerations");
    d.profiler().enable(true);

    std::printf("%s", bench::header(d).c_str());
    std::printf("\nSPHERIC-2 at t = %g s, dp = %g m: %zu particles, %zu non-empty cells (reach %d: %zu neighbour rows of "
                "%d cells per cell); force pass of each form, median (min-max) of %d after %d warm-up, device events\n\n",
                t, scene.physics.dp, n, cp.cells(), reach, grid.rows(), 2 * reach + 1, repeats, warmup);
    {
        // How full the cells are: the CPU form runs a cell's particles 16 at a time, so a cell of
        // 17 walks its candidates twice.
        std::vector<cl_uint> start(cp.cells() + 1);
        d.read(cp.cell_start(), start.data(), start.size());
        std::size_t largest = 0, over = 0, in_over = 0;
        for (std::size_t c = 0; c + 1 < start.size(); ++c) {
            const std::size_t k = start[c + 1] - start[c];
            largest = std::max(largest, k);
            if (k > 16) {
                ++over;
                in_over += k;
            }
        }
        std::printf("particles per non-empty cell: %.1f on average, at most %zu; %.1f %% of the cells hold more than 16, "
                    "with %.1f %% of the particles\n\n",
                    double(n) / double(std::max<std::size_t>(1, cp.cells())), largest,
                    100.0 * double(over) / double(std::max<std::size_t>(1, cp.cells())), 100.0 * double(in_over) / double(n));
    }

    // What a warp executes (geometry only: the same on every device).
    auto stats_k = d.kernel("interaction_stats.cl", "warp_counts", grid.kernel_options());
    const std::size_t groups = (n + 31) / 32;
    auto counts = d.alloc(groups * 4 * sizeof(cl_uint), "warp counts");
    set_loop_args(stats_k, ps, cp, grid, support2);
    stats_k.setArg(7, counts.get());
    d.launch("stats.warp_counts", stats_k, n, 32);
    std::vector<cl_uint> c(groups * 4);
    d.read(counts, c.data(), c.size());
    double candidates = 0, hits = 0, fine_slots = 0, masked_slots = 0;
    for (std::size_t g = 0; g < groups; ++g) {
        candidates += c[4 * g];
        hits += c[4 * g + 1];
        fine_slots += c[4 * g + 2];
        masked_slots += c[4 * g + 3];
    }
    std::printf("per particle: %.0f candidates, %.0f within the support (hit rate %.1f %%); pair-term slots per warp "
                "of 32 for the hits of its lanes: fine %.2fx, masked %.2fx\n\n",
                candidates / double(n), hits / double(n), 100 * hits / candidates, 32 * fine_slots / hits,
                32 * masked_slots / hits);

    // Distances only.
    std::printf("| form | force pass ms | vs fine | max deviation from fine (of the component's largest value) |\n|---|---|---|---|\n");
    {
        auto k = d.kernel("interaction_stats.cl", "distance_only", grid.kernel_options());
        auto hits_out = d.alloc(n * sizeof(cl_uint), "hits");
        set_loop_args(k, ps, cp, grid, support2);
        k.setArg(7, hits_out.get());
        const auto s = bench::measure(warmup, repeats, [&] {
            return bench::time_launches(d, [&] { d.launch("stats.distances", k, n, 128); });
        });
        std::printf("| fine loop, distances only (no pair terms) | %.3f (%.3f-%.3f) | | |\n", 1e3 * s.median, 1e3 * s.min,
                    1e3 * s.max);
    }

    std::vector<float> reference;
    double fine_ms = 0;
    for (const Interaction form : forms) {
        device::Physics phys(d, grid, scene, form);
        d.fill(out, std::numeric_limits<float>::quiet_NaN(), 4 * n);  // poison
        const auto s = bench::measure(warmup, repeats, [&] { return bench::time_launches(d, [&] { phys.forces(ps, cp, out); }); });
        std::vector<float> a(4 * n);
        d.read(out, a.data(), a.size());
        std::string deviation = "(reference)";
        if (reference.empty()) {
            reference = a;
        } else {
            double worst = 0;
            for (int k = 0; k < 4; ++k) {
                double largest = 0, diff = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    largest = std::max(largest, double(std::abs(reference[4 * i + k])));
                    const double e = std::abs(double(a[4 * i + k]) - reference[4 * i + k]);
                    diff = std::isnan(e) ? INFINITY : std::max(diff, e);
                }
                worst = std::max(worst, largest > 0 ? diff / largest : diff);
            }
            char b[64];
            std::snprintf(b, sizeof b, "%.2e", worst);
            deviation = b;
        }
        if (form == Interaction::fine) fine_ms = 1e3 * s.median;
        char ratio[32] = "";
        if (fine_ms > 0) std::snprintf(ratio, sizeof ratio, "%.2fx", fine_ms / (1e3 * s.median));
        std::printf("| %s | %.3f (%.3f-%.3f) | %s | %s |\n", interaction_name(form), 1e3 * s.median, 1e3 * s.min,
                    1e3 * s.max, ratio, deviation.c_str());
    }
    std::printf("\n%.3g neighbour pairs (self excluded) per force pass\n", hits - double(n));
    if (std::find(forms.begin(), forms.end(), Interaction::clusters) != forms.end()) 
        cluster_counts(d, ps, cp, grid, support2, static_cast<float>(list_reach * list_reach), warmup, repeats,
                       candidates);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph interaction-pass benchmark (SPHERIC-2 at t = 0)"};
    std::string devices = "default";
    double dp = 0.006;
    int repeats = 10, warmup = 2;
    std::vector<int> reaches;
    std::vector<std::string> names{"fine", "lanes", "coarse", "clusters"};
    double until = 0;
    std::string within = "memory", cell_order = "arrival";
    bool at_rest = false;
    std::string state;
    double list_buffer = 0;
    app.add_option("--devices", devices, "device selection");
    app.add_option("--list-buffer", list_buffer,
                   "cells and cluster lists wider by this fraction of the support, as run.list_buffer makes them "
                   "(the candidates a pass on tables just built tests; 0: sorted every step)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--dp", dp, "particle spacing (m)");
    app.add_option("--repeats", repeats, "timed repeats");
    app.add_option("--warmup", warmup, "untimed runs first");
    app.add_option("--forms", names, "interaction forms to time, the first is the reference");
    app.add_option("--reach", reaches, "grid reaches to time (1: cells of a support; 2: of half a support along a "
                                       "and b; default: what the simulation picks)");
    auto* until_opt = app.add_option("--until", until,
                   "run the simulation to this time first (fine form, on the device being measured), and measure the "
                   "state it reached, in its memory order: how a warp's work changes once the water moves")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--within-cells", within,
                   "the order of the particles within each cell: memory (as the simulation left them), id (the "
                   "lattice's order, as at t = 0), morton (by the octant of the cell each lies in, then its octant of "
                   "that: compact runs)")
        ->check(CLI::IsMember({"memory", "id", "morton"}));
    app.add_option("--cell-order", cell_order,
                   "the cell pipeline's order within cells when it sorts the particles for the pass (and the run's, "
                   "with --until): arrival (the sort's), morton (order_within_cells: compact runs)")
        ->check(CLI::IsMember({"arrival", "morton"}));
    app.add_option("--state", state,
                   "with --until: a checkpoint of the state reached, read from this file when it exists (and the "
                   "run only continues to --until from it), written to it otherwise")
        ->needs(until_opt);
    app.add_flag("--at-rest", at_rest,
                 "with --until: every velocity set to zero, the positions and densities kept (what the pair terms "
                 "that only moving pairs take, such as artificial viscosity's, cost)")
        ->needs(until_opt);
    CLI11_PARSE(app, argc, argv);
    try {
        std::vector<Interaction> forms;
        for (const auto& s : names) forms.push_back(interaction_from_name(s));
        Scene scene = bench::spheric2_scene(dp);
        scene.run.list_buffer = list_buffer;
        if (reaches.empty()) reaches.push_back(device::reach_for(scene.physics.support(), scene.physics.dp));
        auto opened = cl_rt::open_devices(devices, cl_rt::OpenOptions{true});
        if (until > 0 && opened.size() != 1)
            throw std::runtime_error("--until runs the simulation on the device it measures: --devices must select one "
                                     "device (it selects " + std::to_string(opened.size()) + ")");
        for (std::size_t k = 0; k < opened.size(); ++k) {
            Particles p;
            double t = 0;
            if (until > 0) {
                // The state in motion, in the order the simulation left it in memory (its download
                // keeps that order, and the upload's stable sort keeps it within each cell).
                Options opts;
                opts.devices = devices;
                opts.interaction = Interaction::fine;
                opts.cell_order = cell_order_from_name(cell_order);
                opts.synchronous = false;
                const bool have = !state.empty() && std::ifstream(state).good();
                auto sim = have ? std::make_unique<Simulation>(scene, read_checkpoint(state, &scene), opts)
                                : std::make_unique<Simulation>(scene, opts);
                sim->run_until(until);
                if (!state.empty() && !have) sim->save(state);
                t = sim->time();
                p = sim->particles();
            } else {
                p = scene.build_particles();
            }
            if (within != "memory") p = reordered(p, within, scene);
            if (at_rest) std::fill(p.velocity.begin(), p.velocity.end(), std::array<float, 3>{0.0f, 0.0f, 0.0f});
            for (int reach : reaches)
                run_device(*opened[k], scene, p, t, forms, warmup, repeats, reach, cell_order_from_name(cell_order));
        }
    } catch (const std::exception& e) {
        std::cerr << "clsph-bench-interaction: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
