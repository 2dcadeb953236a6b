#include "run_command.hpp"

#include "dry_run.hpp"
#include "frame_writer.hpp"
#include "interrupt.hpp"
#include "make_simulation.hpp"
#include "output_dir.hpp"
#include "progress.hpp"
#include "report.hpp"
#include "run_plan.hpp"
#include "run_record.hpp"
#include "surface_output.hpp"

#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/scene_io.hpp>
#include <clsph/simulation.hpp>

#include <unistd.h>  // isatty

#include <chrono>
#include <csignal>
#include <sstream>
#include <cmath>
#include <iostream>
#include <memory>

namespace clsph::app {
namespace {

std::vector<std::string> interaction_forms(const Simulation& sim) {
    std::vector<std::string> out;
    for (const auto& d : sim.shares()) out.push_back(interaction_name(d.interaction));
    return out;
}

using clock = std::chrono::steady_clock;

double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

// Thrown from the step callback to leave Simulation::run_until between two steps (the callback
// runs after a step has completed, so the state is whole).
struct StopRun {
    const char* outcome;
};

// The stepping loop and everything it writes; one per run.
class Runner {
public:
    Runner(Simulation& sim, const RunArgs& args, const RunPlan& plan)
        : sim_(sim),
          args_(args),
          plan_(plan),
          record_(plan.out_dir,
                  RunIdentity{args.scene_path, args.overrides, args.command_line, sim.device_names(),
                              interaction_forms(sim), sim.scene().to_json()},
                  sim.scene().probes),
          frames_(plan.out_dir, plan.collection_name, args.csv),
          surfaces_(args.surface || args.surface_every || args.surface_ply || args.surface_spacing > 0 || args.render ||
                            args.video
                        ? std::make_unique<SurfaceOutput>(plan.out_dir, args.surface_every.value_or(0.0), args.surface_ply,
                                                          SurfaceOptions{args.surface_spacing, 0.5}, args.render || args.video)
                        : nullptr),
          progress_(sim.time(), plan.until, plan.steps, isatty(STDERR_FILENO) != 0) {}

    int run(double setup_seconds) {
        totals_.setup_seconds = setup_seconds;
        const auto start = clock::now();
        const std::uint64_t first_step = sim_.info().step;
        std::uint64_t next_frame = 1;
        const double eps = 1e-9 * plan_.every;

        auto on_step = [&](const StepInfo& s) {
            record_.step(s);
            totals_.particle_steps += static_cast<double>(s.particles);
            const int every = sim_.scene().run.probe_every;
            if (every > 0 && s.step % static_cast<std::uint64_t>(every) == 0) sample_probes();
            progress_.update(s, sim_);
            frames_.check();  // a writer error (disk full) ends the run now, not at the end
            if (interrupt_requested()) throw StopRun{"interrupted"};
            if (plan_.steps && s.step - first_step >= *plan_.steps) throw StopRun{"completed"};
        };

        totals_.outcome = "completed";
        int code = exit_ok;
        std::string message, signal;
        try {
            try {
                record_.step(sim_.info());
                sample_probes();
                submit_frame();
                while (sim_.time() < plan_.until - eps) {
                    const double frame_time = static_cast<double>(next_frame) * plan_.every;
                    sim_.run_until(std::min(frame_time, plan_.until), on_step);
                    if (sim_.time() >= frame_time - eps) {
                        submit_frame();
                        ++next_frame;
                    }
                }
            } catch (const StopRun& stop) {
                totals_.outcome = stop.outcome;
                if (totals_.outcome == "interrupted") {
                    signal = signal_name(interrupt_signal());
                    code = interrupt_signal() == SIGTERM ? exit_terminated : exit_interrupted;
                }
            }
            // A final frame where the run stopped off the frame grid (Ctrl-C, SIGTERM, --steps, --until).
            if (frames_.last_time() < sim_.time() - eps) submit_frame();
        } catch (const SimulationError& e) {
            progress_.clear();
            totals_.outcome = "failed";
            message = e.what();
            code = exit_simulation_failed;
            write_last_good();
        } catch (const DeviceError& e) {
            // A device failed mid-run (lost, out of resources): its state is gone; the last frame
            // downloaded is written as the last good state.
            progress_.clear();
            totals_.outcome = "failed";
            message = e.what();
            code = exit_device_failed;
            write_last_good();
        } catch (const Error& e) {
            // A writer or I/O error: say so in run.json, then report it as any other error.
            progress_.clear();
            try {
                frames_.finish();
            } catch (const Error&) {
            }
            try {
                record_.finish("failed", sim_.info(), e.what(), exit_error);
            } catch (const Error&) {
            }
            disarm_abort_record();
            throw;
        }
        progress_.clear();
        const bool failed = code == exit_simulation_failed || code == exit_device_failed;
        frames_.finish();
        totals_.loop_seconds = seconds_since(start);
        record_.finish(totals_.outcome, sim_.info(), message, code, signal);
        disarm_abort_record();

        totals_.last = sim_.info();
        totals_.steps = sim_.info().step - first_step;
        totals_.fluid = sim_.info().fluid;
        totals_.frames = frames_.frames_written();
        totals_.out_dir = plan_.out_dir;
        totals_.collection = frames_.collection_path();
        for (const auto& d : sim_.shares()) {
            // Where the slabs ended up: particles and grid columns per device.
            totals_.devices.push_back(d.device + ": " + std::to_string(d.particles) + " particles, grid columns [" +
                                      std::to_string(d.first_column) + ", " + std::to_string(d.end_column) +
                                      "), interaction " + interaction_name(d.interaction));
        }
        print_summary(std::cout, totals_);
        if (surfaces_ && surfaces_->written() > 0) {
            std::cout << "  surfaces: " << surfaces_->written() << " in " << surfaces_->collection_path() << '\n';
            if (args_.video) std::cout << "  " << surfaces_->make_video() << '\n';
        }
        if (args_.profile && code != exit_device_failed) {
            print_profile(std::cout, sim_.profile(), totals_.steps, sim_.device_names().size());
            for (const auto& d : sim_.shares())  // which form the sph.forces (and sph.density) rows ran
                std::cout << "  interaction form on " << d.device << ": " << interaction_name(d.interaction) << '\n';
        }
        if (failed) {
            std::cout.flush();  // the error is the last thing said
            std::cerr << "clsph: error: " << message << "\nclsph: the last good state is in " << plan_.out_dir
                      << "/last_good.vtu\n";
        }
        return code;
    }

private:
    // Device work outside a step (downloading a frame, sampling the probes): a failure names the
    // step it followed, as a failure within a step does.
    template <class F>
    decltype(auto) after_step(const char* doing, F&& f) {
        try {
            return f();
        } catch (const DeviceError& e) {
            std::ostringstream o;
            o << "after step " << sim_.info().step << ", t = " << sim_.time() << " s, " << doing << ": " << e.what()
              << ". The run stopped; the last good state is at t = " << frames_.last_time() << " s.";
            throw DeviceError(e.code(), o.str(), e.call(), e.device());
        }
    }

    // A frame: downloaded, queued for the writer thread, and the CSV rows up to it pushed to disk,
    // with the run.json a second signal would leave brought up to date.
    void submit_frame() {
        Particles p = after_step("downloading a frame", [&] { return sim_.particles(); });
        frames_.submit(sim_.time(), std::move(p));
        if (surfaces_) after_step("extracting the free surface", [&] {
                surfaces_->at_frame(sim_);
                return 0;
            });
        record_.flush();
        arm_abort_record(record_.json_path(), record_.abort_text(sim_.info()));
    }

    void sample_probes() {
        if (sim_.scene().probes.empty()) return;
        record_.probes(after_step("sampling the probes", [&] { return sim_.sample_probes(); }));
    }

    // The API does not say at what time last_good() was taken (with this loop it is the last frame
    // downloaded), so it goes beside the series rather than into the .pvd at a guessed time.
    void write_last_good() {
        const std::string base = plan_.out_dir + "/last_good";
        write_vtu(base + ".vtu", sim_.last_good());
        if (args_.csv) write_csv(base + ".csv", sim_.last_good());
    }

    Simulation& sim_;
    const RunArgs& args_;
    const RunPlan& plan_;
    RunRecord record_;
    FrameWriter frames_;
    std::unique_ptr<SurfaceOutput> surfaces_;  // --surface
    Progress progress_;
    RunTotals totals_;
};

}  // namespace

// The checks before the first step found the initial state itself out of bounds (a density band
// the hydrostatic start already leaves): a blow-up at step 1, reported as any blow-up is (exit 2,
// run.json "failed", the state at t = 0 the message names in last_good.vtu).
int initial_state_failed(const Scene& scene, const RunArgs& args, const RunPlan& plan, const std::string& message) {
    prepare_output_dir(plan.out_dir, args.force);
    RunRecord record(plan.out_dir, RunIdentity{args.scene_path, args.overrides, args.command_line, {}, {}, scene.to_json()},
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

int run_command(const RunArgs& args) {
    const auto start = clock::now();
    const Scene scene = load_scene(args.scene_path, args.overrides);
    const RunPlan plan = make_plan(args, scene);
    if (args.dry_run) return with_scene_path(args, [&] { return dry_run(scene, args, plan); });
    check_output_dir(plan.out_dir, args.force);  // refuse early, before minutes of kernel builds

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
    std::cout << "clsph: " << args.scene_path << " on";
    for (const auto& d : sim.device_names()) std::cout << ' ' << d;
    std::cout << ": " << sim.info().particles << " particles, ";
    if (std::isfinite(plan.until))
        std::cout << "to t = " << plan.until << " s";
    else
        std::cout << *plan.steps << " steps";
    std::cout << ", output in " << plan.out_dir << std::endl;

    // Only now, with the scene loaded and the devices ready, does the directory appear.
    prepare_output_dir(plan.out_dir, args.force);
    Runner runner(sim, args, plan);
    return runner.run(seconds_since(start));
}

}  // namespace clsph::app
