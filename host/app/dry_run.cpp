#include "dry_run.hpp"

#include "frame_writer.hpp"
#include "make_simulation.hpp"
#include "progress.hpp"
#include "run_ranks.hpp"

#include <clsph/devices.hpp>
#include <clsph/memory_plan.hpp>
#include <clsph/simulation.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

namespace clsph::app {
namespace {

std::string bytes_text(double bytes) {
    char text[32];
    if (bytes < 1024.0 * 1024.0)
        std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
    else if (bytes < 1024.0 * 1024.0 * 1024.0)
        std::snprintf(text, sizeof text, "%.1f MiB", bytes / (1024.0 * 1024.0));
    else
        std::snprintf(text, sizeof text, "%.2f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
    return text;
}

std::string vec_text(const Vec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%g, %g, %g)", v[0], v[1], v[2]);
    return text;
}

// CSV frames hold numbers as exact decimal text: about 120 bytes a particle.
constexpr double csv_bytes_per_particle = 120.0;
// A stats.csv row.
constexpr double stats_bytes_per_step = 70.0;

void print_plan(std::ostream& out, const MemoryPlan& mp, const ChainDevices& chain) {
    char text[512];
    const double n = static_cast<double>(mp.particles);
    out << "  memory plan (predicted on the host, nothing allocated) for " << mp.particles << " particles on "
              << mp.devices.size() << (mp.devices.size() == 1 ? " device" : " devices") << ":\n";
    for (std::size_t d = 0; d < mp.devices.size(); ++d) {
        const auto& x = mp.devices[d];
        const std::string slab = x.slabs > 1 ? " slab " + std::to_string(x.slab + 1) + "/" + std::to_string(x.slabs) : "";
        std::snprintf(text, sizeof text, "  #%zu %s%s: %zu particles owned, arrays for %zu, %zu non-empty cells\n",
                      x.device.index, x.device.name.c_str(), slab.c_str(), x.particles, x.capacity, x.cells);
        out << text;
        std::snprintf(text, sizeof text, "    %-34s %12s %10s  %s\n", "buffer", "bytes", "B/particle", "");
        out << text;
        for (const auto& b : x.buffers) {
            std::snprintf(text, sizeof text, "    %-34s %12zu %10.2f  %s\n", b.name.c_str(), b.bytes,
                          n > 0 ? static_cast<double>(b.bytes) / n : 0.0, b.scales ? "" : "(fixed)");
            out << text;
        }
        const auto& big = x.largest();
        std::snprintf(text, sizeof text,
                      "    %-34s %12zu %10.2f  (%s; %zu B fixed)\n    largest buffer '%s': %s, a single allocation may be "
                      "%s (CL_DEVICE_MAX_MEM_ALLOC_SIZE)%s\n",
                      "total", x.total_bytes(), n > 0 ? static_cast<double>(x.total_bytes()) / n : 0.0,
                      bytes_text(static_cast<double>(x.total_bytes())).c_str(), x.fixed_bytes(), big.name.c_str(),
                      bytes_text(static_cast<double>(big.bytes)).c_str(),
                      bytes_text(static_cast<double>(x.device.max_allocation)).c_str(),
                      big.bytes > x.device.max_allocation ? ": TOO LARGE" : "");
        out << text;
        const std::size_t most = mp.largest_particles(d);
        std::snprintf(text, sizeof text,
                      "    device memory %s (CL_DEVICE_GLOBAL_MEM_SIZE)%s: %s; the largest scene this device's share fits: "
                      "%zu particles (%.3g), physics.dp = %.3g\n",
                      bytes_text(static_cast<double>(x.device.global_memory)).c_str(),
                      x.slabs > 1 ? (", " + bytes_text(static_cast<double>(mp.device_bytes(d))) + " for its " +
                                     std::to_string(x.slabs) + " slabs").c_str()
                                  : "",
                      x.fits() && (x.device.global_memory == 0 || mp.device_bytes(d) <= x.device.global_memory) ? "fits" : "DOES NOT FIT",
                      most, static_cast<double>(most), mp.dp_for(most));
        out << text;
    }
    if (mp.devices.size() > 1) {
        const std::size_t most = mp.largest_particles();
        std::snprintf(text, sizeof text, "  the largest scene these devices fit: %zu particles, physics.dp = %.3g\n", most,
                      mp.dp_for(most));
        out << text;
    }
    for (const auto& note : mp.notes) out << "  note: " << note << '\n';
    if (!chain.rank.empty() && chain.rank.back() > 0) {  // across ranks: whose device each is
        out << "  ranks:";
        for (std::size_t d = 0; d < chain.devices.size(); ++d)
            out << (d ? "," : "") << " #" << chain.devices[d].index << " on rank " << chain.rank[d];
        out << '\n';
    }
}

}  // namespace

int dry_run(const Scene& scene, const RunArgs& args, const RunPlan& plan) {
    // Across MPI ranks rank 0 speaks; every rank plans the whole chain and checks it, and sets up
    // and measures its own devices (their lines gathered to rank 0).
    std::ostringstream quiet;
    std::ostream& out = speaks(args) ? static_cast<std::ostream&>(std::cout) : quiet;
    const auto& ph = scene.physics;
    char text[512];
    out << "clsph run --dry-run: " << args.scene_path << " (scene \"" << scene.name << "\"); nothing is written\n";

    const auto count = scene.count_particles();  // without building them where the scene allows
    struct {
        std::size_t size() const { return n; }
        std::size_t n;
    } const p{static_cast<std::size_t>(count.total())};
    out << "  particles: " << count.total() << " (" << count.fluid << " fluid, " << count.boundary << " boundary)\n";

    // Cells are at least the kernel support wide; the engine keeps only the non-empty ones.
    const double support = ph.support();
    std::uint64_t cells = 1;
    std::string per_axis;
    for (int k = 0; k < 3; ++k) {
        const auto n = static_cast<std::uint64_t>(std::max(1.0, std::floor((scene.domain.max[k] - scene.domain.min[k]) / support)));
        cells *= n;
        per_axis += (k ? " x " : "") + std::to_string(n);
    }
    std::string periodic;
    for (int k = 0; k < 3; ++k)
        if (scene.domain.periodic[k]) periodic += std::string(periodic.empty() ? ", periodic in " : " ") + "xyz"[k];
    out << "  domain: " << vec_text(scene.domain.min) << " to " << vec_text(scene.domain.max) << " m" << periodic
              << "\n  grid: cells >= support 2h = " << support << " m: about " << per_axis << " = " << cells
              << " cells (only non-empty cells are stored)\n";

    const double c0 = scene.sound_speed();
    const double dt_acoustic = ph.cfl * ph.h() / c0;
    std::snprintf(text, sizeof text,
                  "  physics: dp %g m, h %g m, c0 %.4g m/s; acoustic step cfl h / c0 = %.3g s%s\n", ph.dp, ph.h(), c0,
                  dt_acoustic, scene.run.fixed_dt > 0 ? " (the scene fixes dt instead)" : "");
    out << text;
    // Wave makers: what first-order theory made of the waves asked for (docs/scenes.md, wave makers).
    auto wave_maker = [&](const Motion& m, const std::string& key) {
        if (!m.wave_maker) return;
        const WaveMaker& w = *m.wave_maker;
        std::snprintf(text, sizeof text,
                      "  wave maker %s: %s, H %g m, T %g s, d %g m: kd %.4g, wavelength %.4g m, stroke %.4g m (H/S %.4g), ramp %g s\n",
                      key.c_str(), w.kind == WaveMaker::Kind::flap ? "flap" : "piston", w.height, w.period, w.depth, w.k * w.depth,
                      w.wavelength, w.stroke, w.height / w.stroke, w.ramp);
        out << text;
    };
    for (std::size_t i = 0; i < scene.walls.size(); ++i) wave_maker(scene.walls[i].motion, "boundaries.walls[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < scene.solids.size(); ++i) wave_maker(scene.solids[i].motion, "boundaries.boxes[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) wave_maker(scene.meshes[i].motion, "boundaries.meshes[" + std::to_string(i) + "]");
    const double dt_max = scene.run.fixed_dt > 0 ? scene.run.fixed_dt : dt_acoustic;

    // Output: frames, stats rows and probe rows, at the largest step the CFL condition allows.
    const std::uint64_t frames = plan.expected_frames();
    double steps = plan.steps ? static_cast<double>(*plan.steps) : std::ceil(plan.until / dt_max);
    if (plan.steps && std::isfinite(plan.until)) steps = std::min(steps, std::ceil(plan.until / dt_max));
    if (std::isfinite(plan.until))
        std::snprintf(text, sizeof text, "  run: to t = %g s, a frame every %g s: %llu frames; at least %.0f steps\n",
                      plan.until, plan.every, static_cast<unsigned long long>(frames), steps);
    else
        std::snprintf(text, sizeof text, "  run: %.0f steps, a frame every %g s\n", steps, plan.every);
    out << text;
    if (frames) {
        const double vtu = static_cast<double>(frames) * static_cast<double>(FrameWriter::vtu_bytes(p.size()));
        const double csv = args.csv ? static_cast<double>(frames) * csv_bytes_per_particle * static_cast<double>(p.size()) : 0.0;
        const double stats = steps * stats_bytes_per_step;
        out << "  output (estimate): " << bytes_text(vtu) << " of VTU frames"
                  << (args.csv ? ", " + bytes_text(csv) + " of CSV frames" : std::string()) << ", "
                  << bytes_text(stats) << " of stats.csv in " << plan.out_dir << '\n';
    }
    if (std::filesystem::exists(plan.out_dir) && !std::filesystem::is_empty(plan.out_dir))
        out << "  note: " << plan.out_dir << " exists and is not empty; the run needs --force or another --out\n";

    // The memory plan: predicted on the host, nothing allocated (clsph/memory_plan.hpp).
    Options opts;
    opts.synchronous = args.synchronous;
    opts.balance = balance_mode_from_name(args.balance);  // the first cuts (several devices)
    if (!args.interaction.empty()) opts.interaction = interaction_from_name(args.interaction);  // clusters: its lists
    opts.devices = args.devices;
    opts.ranks = args.ranks;
    const ChainDevices chain = chain_devices(opts);  // across ranks: every rank's devices (collective)
    const MemoryPlan mp = plan_memory(scene, chain.devices, opts);
    print_plan(out, mp, chain);
    if (!mp.fits()) check_fits(mp);  // the error a run would stop with, before allocating anything

    out << "  measured: setting up the devices (kernels are built, particles uploaded, one step taken)..." << std::endl;
    const auto t0 = std::chrono::steady_clock::now();
    const auto sim = make_simulation(scene, args);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double dt0 = sim->step().dt;
    const auto measured = sim->memory();
    // This rank's first entry of the plan (entries are slabs; its devices start at chain.first).
    std::size_t first = 0;
    for (std::size_t devices = 0; first < mp.devices.size(); ++first) {
        if (mp.devices[first].slab == 0 && devices++ == chain.first) break;
    }
    std::ostringstream mine;
    for (std::size_t d = 0; d < measured.size(); ++d) {
        const auto& m = measured[d];
        const std::size_t e = first + d;
        const double predicted = e < mp.devices.size() ? static_cast<double>(mp.devices[e].total_bytes()) : 0.0;
        std::snprintf(text, sizeof text,
                      "  %s: %zu particles, peak %s of device memory (%.0f B/particle); predicted %s (%+.2f %%)\n",
                      m.device.c_str(), m.particles, bytes_text(static_cast<double>(m.peak_bytes)).c_str(),
                      m.bytes_per_particle(), bytes_text(predicted).c_str(),
                      m.peak_bytes ? 100.0 * (predicted - static_cast<double>(m.peak_bytes)) / static_cast<double>(m.peak_bytes) : 0.0);
        mine << text;
        {
            // Per buffer, where the measurement and the plan differ by more than 1 % of the total.
            std::map<std::string, double> plan_by_name;
            if (e < mp.devices.size())
                for (const auto& b : mp.devices[e].buffers) plan_by_name[b.name] += static_cast<double>(b.bytes);
            for (const auto& [name, bytes] : m.peak_buffers) plan_by_name.emplace(name, 0.0);
            for (const auto& [name, planned] : plan_by_name) {
                const auto it = m.peak_buffers.find(name);
                const double got = it == m.peak_buffers.end() ? 0.0 : static_cast<double>(it->second);
                if (std::abs(got - planned) <= 0.01 * static_cast<double>(m.peak_bytes)) continue;
                std::snprintf(text, sizeof text, "    %-34s measured %s, predicted %s\n", name.c_str(),
                              bytes_text(got).c_str(), bytes_text(planned).c_str());
                mine << text;
            }
        }
    }
    if (args.ranks && ranks_in(*args.ranks) > 1) {
        for (const auto& lines : gather_text_to(*args.ranks, mine.str(), 0)) out << lines;
    } else {
        out << mine.str();
    }
    std::snprintf(text, sizeof text, "  first time step (one step taken): %.3g s; set-up took %s\n", dt0,
                  format_duration(setup).c_str());
    out << text;
    return exit_ok;
}

}  // namespace clsph::app
