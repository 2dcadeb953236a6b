#include "dry_run.hpp"

#include "frame_writer.hpp"
#include "make_simulation.hpp"
#include "progress.hpp"

#include <clsph/simulation.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
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

}  // namespace

int dry_run(const Scene& scene, const RunArgs& args, const RunPlan& plan) {
    const auto& ph = scene.physics;
    char text[512];
    std::cout << "clsph run --dry-run: " << args.scene_path << " (scene \"" << scene.name << "\"); nothing is written\n";

    const Particles p = scene.build_particles();
    std::size_t fluid = 0;
    for (auto t : p.type) fluid += t == ParticleType::fluid;
    std::cout << "  particles: " << p.size() << " (" << fluid << " fluid, " << p.size() - fluid << " boundary)\n";

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
    std::cout << "  domain: " << vec_text(scene.domain.min) << " to " << vec_text(scene.domain.max) << " m" << periodic
              << "\n  grid: cells >= support 2h = " << support << " m: about " << per_axis << " = " << cells
              << " cells (only non-empty cells are stored)\n";

    const double c0 = scene.sound_speed();
    const double dt_acoustic = ph.cfl * ph.h() / c0;
    std::snprintf(text, sizeof text,
                  "  physics: dp %g m, h %g m, c0 %.4g m/s; acoustic step cfl h / c0 = %.3g s%s\n", ph.dp, ph.h(), c0,
                  dt_acoustic, scene.run.fixed_dt > 0 ? " (the scene fixes dt instead)" : "");
    std::cout << text;
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
    std::cout << text;
    if (frames) {
        const double vtu = static_cast<double>(frames) * static_cast<double>(FrameWriter::vtu_bytes(p.size()));
        const double csv = args.csv ? static_cast<double>(frames) * csv_bytes_per_particle * static_cast<double>(p.size()) : 0.0;
        const double stats = steps * stats_bytes_per_step;
        std::cout << "  output (estimate): " << bytes_text(vtu) << " of VTU frames"
                  << (args.csv ? ", " + bytes_text(csv) + " of CSV frames" : std::string()) << ", "
                  << bytes_text(stats) << " of stats.csv in " << plan.out_dir << '\n';
    }
    if (std::filesystem::exists(plan.out_dir) && !std::filesystem::is_empty(plan.out_dir))
        std::cout << "  note: " << plan.out_dir << " exists and is not empty; the run needs --force or another --out\n";

    std::cout << "  setting up the devices to measure memory (kernels are built, particles uploaded)..." << std::endl;
    const auto t0 = std::chrono::steady_clock::now();
    const auto sim = make_simulation(scene, args);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& m : sim->memory()) {
        std::snprintf(text, sizeof text, "  %s: %zu particles, %s of device memory (%.0f B/particle), room for %zu\n",
                      m.device.c_str(), m.particles, bytes_text(static_cast<double>(m.peak_bytes)).c_str(),
                      m.bytes_per_particle(), m.capacity_particles);
        std::cout << text;
    }
    const double dt0 = sim->step().dt;
    std::snprintf(text, sizeof text, "  first time step (one step taken): %.3g s; set-up took %s\n", dt0,
                  format_duration(setup).c_str());
    std::cout << text;
    return exit_ok;
}

}  // namespace clsph::app
