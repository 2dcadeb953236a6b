// Checkpoint write and read times (docs/checkpoint.md): SPHERIC-2 (or a scene file) at dp, a few
// steps, then `repeats` times Simulation::save (device read + file write + rename), read_checkpoint
// (file read + checksum + scene hash) and a Simulation from it (set-up + upload + restore), with
// the file's size. Host wall clocks; the file goes to --dir (a local disk, not tmpfs, for a fair
// write time). Prints a markdown table.
#include "clsph/checkpoint.hpp"
#include "clsph/scene_io.hpp"
#include "clsph/simulation.hpp"
#include "spheric2_scene.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

using namespace clsph;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph checkpoint benchmark"};
    std::string devices, scene_path, dir = ".";
    std::vector<std::string> overrides;
    double dp = 0.006;
    int steps = 5, repeats = 3;
    app.add_option("--devices", devices, "device selection");
    app.add_option("--scene", scene_path, "scene file (default: SPHERIC-2 built in C++)");
    app.add_option("--set", overrides, "scene overrides KEY=VALUE (repeatable)");
    app.add_option("--dp", dp, "particle spacing for the built-in SPHERIC-2 (m)");
    app.add_option("--steps", steps, "steps before the first checkpoint");
    app.add_option("--repeats", repeats, "timed writes and reads");
    app.add_option("--dir", dir, "where the checkpoint file goes");
    CLI11_PARSE(app, argc, argv);
    try {
        const Scene scene = scene_path.empty() ? bench::spheric2_scene(dp) : load_scene(scene_path, overrides);
        Options o;
        o.devices = devices;
        double t0 = now();
        Simulation sim(scene, o);
        const double setup = now() - t0;
        for (int i = 0; i < steps; ++i) sim.step();
        const std::string path = dir + "/bench_checkpoint.clsph";
        std::vector<double> write, read, restore;
        bool same = true;
        for (int r = 0; r < repeats; ++r) {
            t0 = now();
            sim.save(path);
            write.push_back(now() - t0);
            t0 = now();
            const Checkpoint c = read_checkpoint(path, &scene);
            read.push_back(now() - t0);
            t0 = now();
            Simulation back(scene, c, o);
            restore.push_back(now() - t0);
            same = same && back.info().step == sim.info().step && back.info().particles == sim.info().particles;
        }
        const auto bytes = std::filesystem::file_size(path);
        std::remove(path.c_str());
        std::cout << "| scene | particles | devices | file | save (device read + write) | read + check | new Simulation from it | set-up from the scene |\n"
                  << "|---|---|---|---|---|---|---|---|\n";
        std::printf("| %s dp %.4g | %zu | %zu | %.1f MB | %.0f ms | %.0f ms | %.0f ms | %.0f ms |\n", scene.name.c_str(),
                    scene.physics.dp, sim.info().particles, sim.device_names().size(), static_cast<double>(bytes) / 1e6,
                    1e3 * median(write), 1e3 * median(read), 1e3 * median(restore), 1e3 * setup);
        std::cout << "medians of " << repeats << "; restored state " << (same ? "matches" : "DIFFERS") << '\n';
        return same ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "clsph-bench-checkpoint: " << e.what() << '\n';
        return 1;
    }
}
