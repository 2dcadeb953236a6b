// Interactive frames, the paper's Table 3: per frame one step, one free surface and one image
// (1280 x 720), on the bunny (scenes/bunny.json) at the paper's four sizes. Per size: the scene set
// up, warm-up frames, then --frames timed frames by host clocks (the image's read-back ends each
// frame): physics ms (Simulation::step, synchronous), surface + image ms (Simulation::image: both
// made on the devices), their sum and frames/s, beside the paper's (4 GTX 480, 2010). Also the
// surface alone as downloaded (Simulation::surface), and the devices' peak memory added by the
// frames. Prints a markdown table (BENCHMARKS.md).
//   clsph-bench-interactive [--devices gpu] [--dp 0.00468 0.003925 0.002207 0.001864] [--frames 10]
#include "bench_util.hpp"

#include "clsph/error.hpp"
#include "clsph/render.hpp"
#include "clsph/scene_io.hpp"
#include "clsph/simulation.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace {

// Table 3 of the paper: particles, overall frames/s (physics + rendering), rendering alone.
struct PaperRow {
    double particles, overall, rendering;
};
constexpr PaperRow kPaper[] = {{298e3, 53.2, 64}, {504e3, 28.4, 32}, {1.94e6, 14.3, 17}, {3.05e6, 9.86, 12.6}};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph-bench-interactive: step + surface + image per frame (the paper's Table 3)"};
    std::string devices, scene_path = "scenes/bunny.json", png;
    std::vector<std::string> overrides;
    std::vector<double> dps{0.00468, 0.003925, 0.002207, 0.001864};  // ~298 k, 504 k, 1.94 M, 3.05 M particles
    int frames = 10, warmup = 3, settle = 50;
    bool profile = false;
    app.add_option("--devices", devices, "device selection");
    app.add_option("--scene", scene_path, "scene file");
    app.add_option("--set", overrides, "scene overrides KEY=VALUE (repeatable)");
    app.add_option("--dp", dps, "particle spacings, one row each");
    app.add_option("--frames", frames, "timed frames per size")->check(CLI::PositiveNumber);
    app.add_option("--warmup", warmup, "untimed frames first");
    app.add_option("--settle", settle, "steps before the first frame (the water starts moving)");
    app.add_option("--png", png, "write the last image of the last size here");
    app.add_flag("--profile", profile, "per-kernel device time of the frames (surface.*, render.*), per size");
    CLI11_PARSE(app, argc, argv);
    try {
        std::printf("## Interactive frames, %s, %s\n\n", scene_path.c_str(), clsph::bench::today().c_str());
        std::string rows;
        for (std::size_t i = 0; i < dps.size(); ++i) {
            auto o = overrides;
            o.push_back("physics.dp=" + std::to_string(dps[i]));
            const clsph::Scene scene = clsph::load_scene(scene_path, o);
            clsph::Options opts;
            opts.devices = devices;
            opts.synchronous = true;  // each frame's step ends before its surface: timed apart
            opts.profile = profile;
            clsph::Simulation sim(scene, opts);
            if (i == 0)
                for (const auto& n : sim.device_names()) std::printf("device: %s\n", n.c_str());
            for (int s = 0; s < settle; ++s) sim.step();
            std::size_t before = 0;
            for (const auto& m : sim.memory()) before += m.peak_bytes;
            const auto camera = clsph::camera_for(scene);
            std::vector<double> physics, picture, frame, surface;
            clsph::Image image;
            for (int f = 0; f < warmup + frames; ++f) {
                const auto t0 = std::chrono::steady_clock::now();
                sim.step();
                const double tp = seconds_since(t0);
                const auto t1 = std::chrono::steady_clock::now();
                image = sim.image(camera);
                const double ti = seconds_since(t1);
                if (f >= warmup) {
                    physics.push_back(tp);
                    picture.push_back(ti);
                    frame.push_back(tp + ti);
                }
            }
            if (profile) {
                auto k = sim.profile();
                std::sort(k.begin(), k.end(), [](const auto& a, const auto& b) { return a.seconds > b.seconds; });
                double total = 0;
                for (const auto& e : k)
                    if (e.name.rfind("surface", 0) == 0 || e.name.rfind("render", 0) == 0) total += e.seconds;
                std::fprintf(stderr, "dp %.5f: surface.* + render.* device time %.2f ms per frame; top launches:\n", dps[i],
                             1e3 * total / (warmup + frames));
                for (std::size_t e = 0; e < k.size() && e < 14; ++e)
                    std::fprintf(stderr, "  %-28s %8zu calls %9.3f ms per frame\n", k[e].name.c_str(), k[e].calls,
                                 1e3 * k[e].seconds / (warmup + frames));
            }
            std::size_t triangles = 0;
            for (int r = 0; r < 3; ++r) {
                const auto t0 = std::chrono::steady_clock::now();
                triangles = sim.surface().triangles.size();
                surface.push_back(seconds_since(t0));
            }
            std::size_t after = 0;
            for (const auto& m : sim.memory()) after += m.peak_bytes;
            const auto p = clsph::bench::summarize(physics), im = clsph::bench::summarize(picture),
                       fr = clsph::bench::summarize(frame), su = clsph::bench::summarize(surface);
            // The paper's row nearest in particle count.
            const PaperRow* paper = &kPaper[0];
            for (const auto& row : kPaper)
                if (std::abs(row.particles - double(sim.info().particles)) < std::abs(paper->particles - double(sim.info().particles)))
                    paper = &row;
            char line[640];
            std::snprintf(line, sizeof line,
                          "| %.5f | %zu | %zu | %.2f | %.1f (%.1f-%.1f) | %.1f | **%.1f** | %.2f (%.0fk) | %.1fx | %.0f | %.1f |\n",
                          dps[i], sim.info().particles, triangles, 1e3 * p.median, 1e3 * im.median, 1e3 * im.min, 1e3 * im.max,
                          1e3 * fr.median, 1.0 / fr.median, paper->overall, paper->particles / 1e3,
                          (1.0 / fr.median) / paper->overall, 1e3 * su.median, double(after - before) / 1048576.0);
            rows += line;
            std::fprintf(stderr, "dp %.5f done: %s", dps[i], line);
            if (i + 1 == dps.size() && !png.empty()) clsph::write_png(png, image);
        }
        std::printf("\n%d frames per size after %d warm-up frames and %d steps; host clocks; medians (min-max)\n\n", frames,
                    warmup, settle);
        std::printf("| dp | particles | triangles | physics ms | surface + image ms | frame ms | frames/s | paper frames/s "
                    "(particles) | vs paper | surface() ms, downloaded | MiB added |\n|---|---|---|---|---|---|---|---|---|---|---|\n%s",
                    rows.c_str());
    } catch (const clsph::Error& e) {
        std::cerr << "clsph-bench-interactive: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
