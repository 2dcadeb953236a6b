// The SPHERIC-2 benchmark (bench/spheric2_scene.hpp): particle counts, average ms/step over the
// first 0.1 s of simulated time after set-up, wall seconds per simulated second, the per-kernel
// breakdown, and device bytes per particle. Prints a markdown report.
#include "spheric2_scene.hpp"

#include "bench_util.hpp"
#include "clsph/error.hpp"
#include "clsph/simulation.hpp"
#include "clsph/testing.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <iostream>

#include <sys/resource.h>

namespace {
// Writes a timeline (device, command, start ns, end ns) as CSV and prints, per device, where it
// idles: the gaps between one command's end and the next one's start, summed by the command that
// ends the gap (the wait before it), in ms per step over `steps` steps.
void write_trace(const std::string& path, std::vector<clsph::CommandSpan> spans, double steps) {
    std::ofstream out(path);
    if (!out) throw clsph::Error("--trace: cannot write " + path);
    out << "device,command,start_ns,end_ns\n";
    std::stable_sort(spans.begin(), spans.end(), [](const clsph::CommandSpan& a, const clsph::CommandSpan& b) {
        return a.device != b.device ? a.device < b.device : a.start_ns < b.start_ns;
    });
    std::map<std::string, std::map<std::string, double>> idle;  // device -> next command -> seconds
    std::map<std::string, double> busy_span;
    std::uint64_t last_end = 0;
    for (std::size_t i = 0; i < spans.size(); ++i) {
        const auto& s = spans[i];
        out << '"' << s.device << "\"," << s.name << ',' << s.start_ns << ',' << s.end_ns << '\n';
        const bool first = i == 0 || spans[i - 1].device != s.device;
        if (!first && s.start_ns > last_end) idle[s.device][s.name] += static_cast<double>(s.start_ns - last_end) * 1e-9;
        if (first) {
            busy_span[s.device] -= static_cast<double>(s.start_ns) * 1e-9;
            last_end = s.end_ns;
        }
        last_end = std::max(last_end, s.end_ns);
        if (i + 1 == spans.size() || spans[i + 1].device != s.device) busy_span[s.device] += static_cast<double>(last_end) * 1e-9;
    }
    std::printf("\nidle time per device, by the command that ends the wait (ms/step; trace in %s):\n", path.c_str());
    for (auto& [device, by] : idle) {
        std::vector<std::pair<double, std::string>> rows;
        double total = 0;
        for (auto& [name, sec] : by) {
            rows.push_back({sec, name});
            total += sec;
        }
        std::sort(rows.rbegin(), rows.rend());
        std::printf("  %s: %.3f ms/step idle of %.3f ms/step from first to last command\n", device.c_str(),
                    1e3 * total / steps, 1e3 * busy_span[device] / steps);
        for (std::size_t k = 0; k < rows.size() && k < 8; ++k)
            std::printf("    before %s: %.3f\n", rows[k].second.c_str(), 1e3 * rows[k].first / steps);
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph SPHERIC-2 benchmark"};
    std::string devices;
    double dp = 0.006, until = 0.1;
    std::string interaction = "auto", cell_order = "auto";
    std::string balance = "dynamic", balance_log, trace;
    bool synchronous = false, whole_force_pass = false;
    std::size_t max_steps = 0, slabs = 1;
    std::string scene_file, viscosity = "artificial";
    double nu = clsph::PhysicsParams{}.kinematic_viscosity;
    double list_buffer = 0;
    app.add_option("--viscosity", viscosity, "viscosity model: artificial | laminar | laminar+sps (physics.viscosity)")
        ->check(CLI::IsMember({"artificial", "laminar", "laminar+sps"}));
    app.add_option("--nu", nu, "kinematic viscosity of the laminar model (m^2/s; physics.kinematic_viscosity)");
    app.add_option("--scene", scene_file, "a scene file instead of the built-in SPHERIC-2 (its dp replaced by --dp; its probes sampled at the end)");
    app.add_option("--list-buffer", list_buffer,
                   "cell tables and cluster lists kept over steps with this buffer, a fraction of the support "
                   "(run.list_buffer; 0: sorted every step)");
    app.add_option("--steps", max_steps, "time at most N steps (0: no limit; a billion particles: a few)");
    app.add_option("--devices", devices, "device selection (default: $CLSPH_DEVICES or every GPU)");
    app.add_option("--dp", dp, "particle spacing (m)");
    app.add_option("--until", until, "simulated seconds to time");
    app.add_option("--interaction", interaction, "interaction form: auto | fine | lanes | coarse | clusters")
        ->check(CLI::IsMember({"auto", "fine", "lanes", "coarse", "clusters"}));
    app.add_option("--cell-order", cell_order, "order within cells: auto | arrival | morton")
        ->check(CLI::IsMember({"auto", "arrival", "morton"}));
    app.add_option("--balance", balance, "several devices: dynamic | static | off");
    app.add_option("--balance-log", balance_log, "several devices: per-step balancer CSV");
    app.add_option("--slabs", slabs, "open each device as N slabs (what several slabs cost, on one device)");
    app.add_flag("--synchronous", synchronous, "wait for every step on the host (the step ahead off)");
    app.add_flag("--whole-force-pass", whole_force_pass,
                 "several devices or slabs: the whole force pass after the merge (the halo not overlapped with the interior)");
    app.add_option("--trace", trace, "CSV of every command's device start and end (ns) in the timed window, and a "
                                     "summary of where each device idles");
    CLI11_PARSE(app, argc, argv);
    try {
        using clock = std::chrono::steady_clock;
        const auto t0 = clock::now();
        clsph::Scene scene = clsph::bench::spheric2_scene(dp);
        if (!scene_file.empty()) {
            scene = clsph::Scene::from_file(scene_file);
            scene.physics.dp = dp;
        }
        if (viscosity == "laminar") scene.physics.viscosity = clsph::Viscosity::laminar;
        if (viscosity == "laminar+sps") scene.physics.viscosity = clsph::Viscosity::laminar_sps;
        scene.physics.kinematic_viscosity = nu;
        scene.run.list_buffer = list_buffer;
        clsph::Options opts;
        opts.devices = devices;
        opts.profile = true;
        opts.interaction = clsph::interaction_from_name(interaction);
        opts.cell_order = clsph::cell_order_from_name(cell_order);
        opts.balance = clsph::balance_mode_from_name(balance);
        opts.balance_log = balance_log;
        opts.trace = !trace.empty();
        opts.synchronous = synchronous;  // default: steps ahead of the host on one device (issue 15)
        if (max_steps) opts.step_limit = max_steps;
        if (slabs > 1 || whole_force_pass) {
            clsph::testing::Seams seams;
            seams.slabs = slabs;
            seams.whole_force_pass = whole_force_pass;
            clsph::testing::set_seams(opts, std::move(seams));
        }
        opts.on_setup = [t0](const std::string& line) {
            std::fprintf(stderr, "  set-up %.1f s: %s\n", std::chrono::duration<double>(clock::now() - t0).count(), line.c_str());
        };
        clsph::Simulation sim(scene, opts);
        const double setup = std::chrono::duration<double>(clock::now() - t0).count();
        // Counted on the devices: no particle comes to the host (a billion would be ~50 GB).
        struct {
            std::size_t size() const { return n; }
            std::size_t n;
        } const p{sim.info().particles};
        const std::size_t fluid = sim.info().fluid;
        std::printf("## SPHERIC-2, dp = %g m, interaction %s (%s)\n\n", dp, interaction.c_str(),
                    clsph::bench::today().c_str());
        for (const auto& sh : sim.shares())
            std::printf("device: %s, interaction form %s, cells in %s order\n", sh.device.c_str(),
                        clsph::interaction_name(sh.interaction), clsph::cell_order_name(sh.cell_order));
        std::printf("particles: %zu (boundary %zu, fluid %zu); reference at dp 0.006: 4,989,696 (1,975,146 + 3,014,550)\n",
                    p.size(), p.size() - fluid, fluid);
        std::printf("set-up (particles + device + first force pass): %.1f s\n", setup);
        for (const auto& sh : sim.shares())
            if (sh.calibrated_whole_scene_seconds > 0)
                std::printf("calibration of %s: %.2f ms per force pass over the whole scene (fixed %.3f ms)\n",
                            sh.device.c_str(), 1e3 * sh.calibrated_whole_scene_seconds, 1e3 * sh.calibrated_fixed_seconds);
        {
            const auto sh = sim.shares();
            if (sh.size() > 1) {
                std::printf("first cut:");
                for (const auto& x : sh) std::printf(" [%zu, %zu)", x.first_column, x.end_column);
                std::printf("\n");
            }
        }
        sim.profile();  // discard set-up launches from the breakdown
        sim.take_trace();
        std::size_t received0 = 0;
        for (const auto& sh : sim.shares()) received0 += sh.received_bytes;
        const auto t1 = clock::now();
        double steps = 0;
        if (max_steps) {
            for (std::size_t k = 0; k < max_steps && sim.time() < until; ++k) steps = static_cast<double>(sim.step().step);
        } else {
            sim.run_until(until, [&](const clsph::StepInfo& s) {
                steps = static_cast<double>(s.step);
                if (s.step % 500 == 0) std::fprintf(stderr, "  t = %.4f s, %llu steps\n", s.time, (unsigned long long)s.step);
            });
        }
        const double wall = std::chrono::duration<double>(clock::now() - t1).count();
        std::printf("steps: %.0f to t = %.3f s; wall %.2f s\n", steps, sim.time(), wall);
        std::printf("**%.2f ms/step**, %.0f wall s per simulated s, %.3g particle-steps/s\n\n", 1e3 * wall / steps,
                    wall / sim.time(), static_cast<double>(p.size()) * steps / wall);
        if (list_buffer > 0) {
            const auto tb = sim.table_builds();
            std::printf("cell tables built %zu times in %.0f steps (every %.1f steps; list buffer %g of the support)\n\n",
                        tb.builds, steps, steps / static_cast<double>(tb.builds), list_buffer);
        }
        auto prof = sim.profile();
        if (!trace.empty()) write_trace(trace, sim.take_trace(), steps);
        double total = 0;
        for (const auto& k : prof) total += k.seconds;
        std::sort(prof.begin(), prof.end(), [](const auto& a, const auto& b) { return a.seconds > b.seconds; });
        const bool several = sim.device_names().size() > 1;
        std::printf(several ? "| kernel | device | calls | total ms | ms/step | %% |\n|---|---|---|---|---|---|\n"
                            : "| kernel | calls | total ms | ms/step | %% |\n|---|---|---|---|---|\n");
        for (const auto& k : prof) {
            std::printf("| %s |", k.name.c_str());
            if (several) std::printf(" %s |", k.device.substr(0, k.device.find(' ')).c_str());
            std::printf(" %zu | %.1f | %.3f | %.1f |\n", k.calls, 1e3 * k.seconds, 1e3 * k.seconds / steps,
                        100 * k.seconds / total);
        }
        if (several) total /= static_cast<double>(sim.device_names().size());
        std::printf(several ? "\ndevice time in kernels per device (mean): %.2f ms/step of %.2f ms/step wall\n"
                            : "\ndevice time in kernels: %.2f ms/step of %.2f ms/step wall\n", 1e3 * total / steps, 1e3 * wall / steps);
        std::printf("the rest (host, waits, gaps between launches): %.1f %% of the step; steps %s\n",
                    100.0 * (1.0 - total / wall), sim.steps_ahead() ? "ahead of the host" : "synchronous");
        if (sim.steps_ahead())
            std::printf("steps taken ahead of the host: %llu; computed ahead and thrown away: %llu\n",
                        static_cast<unsigned long long>(sim.steps_taken_ahead()),
                        static_cast<unsigned long long>(sim.steps_thrown_ahead()));
        const auto shares = sim.shares();
        if (shares.size() > 1) {
            std::printf("\nhost wall time per step phase (ms/step):\n");
            for (const auto& ph : sim.host_phases()) std::printf("  %s: %.2f\n", ph.name.c_str(), 1e3 * ph.seconds / steps);
            double tmax = 0, tsum = 0;
            for (const auto& sh : shares) {
                tmax = std::max(tmax, sh.force_seconds);
                tsum += sh.force_seconds;
                std::printf("share of %s: %zu particles, columns [%zu, %zu), last force pass %.2f ms\n", sh.device.c_str(),
                            sh.particles, sh.first_column, sh.end_column, 1e3 * sh.force_seconds);
            }
            std::printf("imbalance of the last step's force passes (max/mean): %.3f\n", tmax / (tsum / double(shares.size())));
            std::size_t received = 0, ghosts = 0;
            for (const auto& sh : shares) {
                received += sh.received_bytes;
                ghosts += sh.ghosts;
            }
            std::printf("copied between devices: %.2f MB/step (ghosts held now: %zu particles)\n",
                        1e-6 * static_cast<double>(received - received0) / steps, ghosts);
        }
        for (const auto& m : sim.memory())
            std::printf("memory on %s: peak %.1f MiB for %zu particles = %.1f bytes/particle (capacity %zu)\n",
                        m.device.c_str(), static_cast<double>(m.peak_bytes) / 1048576.0, m.particles, m.bytes_per_particle(),
                        m.capacity_particles);
        for (const auto& pr : sim.sample_probes())  // sampled on the devices, no particle downloaded
            std::printf("probe %s at t = %.4f s: %g\n", pr.name.c_str(), sim.time(), pr.value);
        struct rusage ru {};
        getrusage(RUSAGE_SELF, &ru);
        std::printf("peak host memory (max RSS): %.2f GiB\n", static_cast<double>(ru.ru_maxrss) / (1024.0 * 1024.0));
    } catch (const clsph::Error& e) {
        std::cerr << "clsph-bench-sph: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
