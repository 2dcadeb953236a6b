#include "run_command.hpp"

#include "dry_run.hpp"
#include "interrupt.hpp"
#include "make_simulation.hpp"
#include "output_dir.hpp"
#include "resume.hpp"
#include "run_plan.hpp"
#include "run_ranks.hpp"
#include "run_record.hpp"
#include "serve/live_server.hpp"

#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/ranks.hpp>
#include <clsph/scene_io.hpp>
#include <clsph/simulation.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>

namespace clsph::app {
namespace {

// The checks before the first step found the initial state itself out of bounds (a density band
// the hydrostatic start already leaves): a blow-up at step 1, reported as any blow-up is (exit 2,
// run.json "failed", the state at t = 0 the message names in last_good.vtu).
int initial_state_failed(const Scene& scene, const RunArgs& args, const RunPlan& plan, const std::string& message) {
    prepare_output_dir(plan.out_dir, args.force);
    RunRecord record(plan.out_dir, RunIdentity{args.scene_path, args.overrides, args.command_line, {}, {}, {}, scene.to_json(), {}, {}},
                     scene.probes);
    const Particles initial = scene.build_particles();
    write_vtu(plan.out_dir + "/last_good.vtu", initial);
    if (args.csv) write_csv(plan.out_dir + "/last_good.csv", initial);
    StepInfo at_start;  // step 0, t = 0
    at_start.particles = initial.size();
    record.finish("failed", at_start, message, exit_simulation_failed);
    std::cerr << "clsph: error: " << message << "\nclsph: the last good state is in " << plan.out_dir << "/last_good.vtu\n";
    return exit_simulation_failed;
}

// What a run across MPI ranks does not do yet, refused before anything starts.
RunArgs across_ranks(RunArgs args) {
    if (!args.ranks || ranks_in(*args.ranks) < 2) return args;
    auto refuse = [](const char* what) {
        throw Error(std::string(what) + " is not supported across MPI ranks yet; run it in one process (docs/mpi.md lists what runs across ranks)");
    };
    if (args.serve) refuse("--serve");
    return args;
}

// --serve: the live view's server, listening before the kernels build (a port in use is an error
// before anything is written), and the run made synchronous so that the run loop can render and
// pause between two steps.
std::unique_ptr<serve::LiveServer> start_live_view(RunArgs& args, const Scene& scene, const RunPlan& plan) {
    if (!args.serve) return nullptr;
    args.live = std::make_shared<serve::LiveView>(0, plan.until, plan.steps);
    const Vec3 lo = scene.domain.min, hi = scene.domain.max;
    const double size = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    auto server = std::make_unique<serve::LiveServer>(serve::ServeAddress{args.serve_host, *args.serve}, *args.live,
                                                      camera_for(scene), size);
    std::cout << "clsph: live view at " << server->url();
    if (serve::is_loopback(args.serve_host))
        std::cout << " (this machine only; from another: ssh -L " << *args.serve << ":localhost:" << *args.serve
                  << " THIS_HOST, then http://localhost:" << *args.serve << "/)\n";
    else
        std::cout << "\nclsph: warning: --serve-host " << args.serve_host
                  << ": the live view is open to the network, without authentication: anyone who reaches it can pause "
                     "the run and write frames and checkpoints (docs/live_view.md)\n";
    if (!args.synchronous)
        std::cout << "clsph: --serve: steps wait for the host (as --synchronous), so that images are taken between steps\n";
    args.synchronous = true;
    std::cout.flush();
    return server;
}

}  // namespace

int run_command(const RunArgs& given) {
    RunArgs args = across_ranks(given);
    if (args.no_checkpoint && args.on_device_failure == "continue")
        throw Error("--no-checkpoint with --on-device-failure continue: going on after a device failure starts from a "
                    "checkpoint; drop one of them");
    const auto start = std::chrono::steady_clock::now();
    Scene scene = load_scene(args.scene_path, args.overrides);
    if (!args.ranks || rank_of(*args.ranks) == 0)
        for (const auto& note : scene.notes) std::cout << "clsph: note: " << args.scene_path << ": " << note << '\n';
    if (!args.render_method.empty())  // --render-method: recorded in run.json's scene with the rest
        scene.render.method = args.render_method == "splat" ? RenderMethod::splat : RenderMethod::surface;
    const RunPlan plan = make_plan(args, scene);
    if (args.dry_run) return with_scene_path(args, [&] { return dry_run(scene, args, plan); });
    if (!args.resume_dir.empty()) return resume_run(scene, args, plan, start);
    check_output_dir(plan.out_dir, args.force);  // refuse early, before minutes of kernel builds
    const auto live_server = start_live_view(args, scene, plan);

    // From here on Ctrl-C and SIGTERM are caught: during set-up (kernel builds can take minutes)
    // they end it before anything is written; a second one kills at once.
    install_interrupt_handler();
    std::unique_ptr<Simulation> simulation;
    try {
        simulation = make_simulation(scene, args);
    } catch (const SimulationError& e) {
        return initial_state_failed(scene, args, plan, e.what());
    }
    if (interrupt_requested()) {
        std::cerr << "clsph: " << signal_name(interrupt_signal()) << " during set-up: stopped before any output was written\n";
        return interrupt_signal() == SIGTERM ? exit_terminated : exit_interrupted;
    }
    Simulation& sim = *simulation;
    const auto names = all_device_names(sim, args);
    if (speaks(args)) {
        std::cout << "clsph: " << args.scene_path << " on";
        for (const auto& d : names) std::cout << (args.ranks ? "\n  " : " ") << d;
        std::cout << (args.ranks ? "\n  " : ": ") << sim.info().particles << " particles, ";
        if (std::isfinite(plan.until))
            std::cout << "to t = " << plan.until << " s";
        else
            std::cout << *plan.steps << " steps";
        std::cout << ", output in " << plan.out_dir << std::endl;
        // Only now, with the scene loaded and the devices ready, does the directory appear.
        prepare_output_dir(plan.out_dir, args.force);
    }
    if (args.ranks) wait_for_all(*args.ranks);  // the directory is there before any rank writes
    return run_with_failover(sim, args, plan, nullptr, scene, start);
}

}  // namespace clsph::app
