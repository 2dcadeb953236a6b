// The free surface per frame (Simulation::surface): a scene (default scenes/bunny.json) on the
// devices, a few steps, then the surface timed by host clocks over repeats (median (min-max) after
// a warm-up), with its triangles, vertices and the devices' peak memory before and after. The mesh
// of the last repeat can be written as VTP for a look.
#include "bench_util.hpp"

#include "clsph/error.hpp"
#include "clsph/mesh.hpp"
#include "clsph/render.hpp"
#include "clsph/scene_io.hpp"
#include "clsph/simulation.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

int main(int argc, char** argv) {
    CLI::App app{"clsph surface benchmark"};
    std::string devices, scene_path = "scenes/bunny.json", vtp, png;
    std::vector<std::string> overrides;
    int steps = 20, repeats = 5, warmup = 1;
    double spacing = 0;
    app.add_option("--devices", devices, "device selection");
    app.add_option("--scene", scene_path, "scene file");
    app.add_option("--set", overrides, "scene overrides KEY=VALUE (repeatable)");
    app.add_option("--steps", steps, "steps before the surface is taken");
    app.add_option("--repeats", repeats, "timed surfaces");
    app.add_option("--warmup", warmup, "untimed surfaces first");
    app.add_option("--spacing", spacing, "sample spacing (m; default dp/2)");
    app.add_option("--vtp", vtp, "write the last surface here");
    app.add_option("--png", png, "also time an image of each surface (the scene's camera) and write the last here");
    CLI11_PARSE(app, argc, argv);
    try {
        const clsph::Scene scene = clsph::load_scene(scene_path, overrides);
        clsph::Options opts;
        opts.devices = devices;
        clsph::Simulation sim(scene, opts);
        for (int i = 0; i < steps; ++i) sim.step();
        std::size_t before = 0;
        for (const auto& m : sim.memory()) before += m.peak_bytes;
        clsph::SurfaceOptions so;
        so.spacing = spacing;
        clsph::TriangleMesh mesh;
        clsph::Image image;
        std::vector<double> t, ti;
        const auto camera = clsph::camera_for(scene);
        for (int r = 0; r < warmup + repeats; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            mesh = sim.surface(so);
            const auto t1 = std::chrono::steady_clock::now();
            if (!png.empty()) image = sim.render(mesh, camera);
            const auto t2 = std::chrono::steady_clock::now();
            if (r >= warmup) {
                t.push_back(std::chrono::duration<double>(t1 - t0).count());
                ti.push_back(std::chrono::duration<double>(t2 - t1).count());
            }
        }
        std::size_t after = 0;
        for (const auto& m : sim.memory()) after += m.peak_bytes;
        const auto sum = clsph::bench::summarize(t);
        std::printf("## Free surface, %s (%s)\n\n", scene.name.c_str(), clsph::bench::today().c_str());
        for (const auto& n : sim.device_names()) std::printf("device: %s\n", n.c_str());
        std::printf("particles: %zu (fluid %zu), dp %g m, sample spacing %g m, after %d steps\n", sim.info().particles,
                    sim.info().fluid, scene.physics.dp, spacing > 0 ? spacing : scene.physics.dp / 2, steps);
        std::printf("surface: %zu triangles, %zu vertices\n", mesh.triangles.size(), mesh.positions.size());
        std::printf("**%.1f ms per surface** (median of %d; min %.1f, max %.1f; host clocks, everything included)\n",
                    1e3 * sum.median, repeats, 1e3 * sum.min, 1e3 * sum.max);
        std::printf("device memory (peak, all devices): %.1f MiB before, %.1f MiB after the surfaces (+%.1f MiB)\n",
                    double(before) / 1048576.0, double(after) / 1048576.0, double(after - before) / 1048576.0);
        if (!png.empty()) {
            const auto si = clsph::bench::summarize(ti);
            std::printf("**%.1f ms per image** (%u x %u, median of %d; min %.1f, max %.1f; host clocks, read-back and "
                        "compositing included)\n",
                        1e3 * si.median, camera.width, camera.height, repeats, 1e3 * si.min, 1e3 * si.max);
            clsph::write_png(png, image);
        }
        if (!vtp.empty()) clsph::write_vtp(vtp, mesh);
    } catch (const clsph::Error& e) {
        std::cerr << "clsph-bench-surface: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
