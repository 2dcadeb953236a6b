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

#include <clsph/checkpoint.hpp>
#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/scene_io.hpp>
#include <clsph/simulation.hpp>

#include <nlohmann/json.hpp>
#include <unistd.h>  // isatty

#include <ctime>
#include <fstream>
#include <iterator>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <csignal>
#include <sstream>
#include <cmath>
#include <iostream>
#include <memory>

namespace clsph::app {
namespace {

// Across MPI ranks: rank 0 speaks and writes the run's files; every rank writes its frame pieces.
bool speaks(const RunArgs& args) { return !args.ranks || rank_of(*args.ranks) == 0; }

// Every device of the run: this process's, or across ranks every rank's ("rank R: #i name").
std::vector<std::string> all_device_names(const Simulation& sim, const RunArgs& args) {
    const auto mine = sim.device_names();
    if (!args.ranks) return mine;
    std::string joined;
    for (const auto& n : mine) joined += n + '\n';
    std::vector<std::string> out;
    const auto all = gather_text(*args.ranks, joined);
    for (std::size_t r = 0; r < all.size(); ++r) {
        std::istringstream lines(all[r]);
        for (std::string line; std::getline(lines, line);) out.push_back("rank " + std::to_string(r) + ": " + line);
    }
    return out;
}

std::vector<std::string> interaction_forms(const Simulation& sim) {
    std::vector<std::string> out;
    for (const auto& d : sim.shares()) out.push_back(interaction_name(d.interaction));
    return out;
}

using clock = std::chrono::steady_clock;

std::string read_text_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error("cannot read " + path);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

// clsph resume: where the run goes on from and what the output directory already holds.
struct ResumeState {
    ResumePoint point;
    std::vector<PvdEntry> frames;     // the collection as the run left it
    std::string start_time;           // the run's first start
    std::vector<std::string> resumes; // JSON objects, this one last
};

// Thrown from the step callback to leave Simulation::run_until between two steps (the callback
// runs after a step has completed, so the state is whole).
struct StopRun {
    const char* outcome;
};

// The stepping loop and everything it writes; one per run.
class Runner {
public:
    Runner(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* resume = nullptr)
        : sim_(sim),
          args_(args),
          plan_(plan),
          resume_(resume),
          record_(plan.out_dir,
                  RunIdentity{args.scene_path, args.overrides, args.command_line, all_device_names(sim, args),
                              interaction_forms(sim), sim.scene().to_json(), resume ? resume->start_time : std::string(),
                              resume ? resume->resumes : std::vector<std::string>{}},
                  sim.scene().probes, resume ? &resume->point : nullptr, speaks(args)),
          frames_(plan.out_dir, plan.collection_name, FrameFormat{args.csv, args.compress, args.pieces, args.ranks.get()},
                  FrameFilter::from_options(args.output_stride, args.output_box, args.fields)),
          surfaces_(args.surface || args.surface_every || args.surface_ply || args.surface_spacing > 0 || args.render ||
                            args.video
                        ? std::make_unique<SurfaceOutput>(plan.out_dir, args.surface_every.value_or(0.0), args.surface_ply,
                                                          SurfaceOptions{args.surface_spacing, 0.5}, args.render || args.video)
                        : nullptr),
          progress_(sim.time(), plan.until, plan.steps, isatty(STDERR_FILENO) != 0) {
        if (resume_) {
            frames_.resume_at(resume_->frames, resume_->point.time);
            last_checkpoint_step_ = resume_->point.step;
            if (args_.checkpoint_every)
                next_checkpoint_ = (std::floor(sim.time() / *args_.checkpoint_every + 1e-9) + 1) * *args_.checkpoint_every;
        }
    }

    // After run() returned exit_device_failed with --on-device-failure continue: the device that
    // failed (its label) and the error; empty otherwise.
    const std::string& failed_device() const { return failed_device_; }
    const std::string& failure_message() const { return failure_message_; }

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
            if (speaks(args_)) progress_.update(s, sim_);
            frames_.check();  // a writer error (disk full) ends the run now, not at the end
            // Across ranks every rank stops at the same step, whichever got the signal.
            if (args_.ranks ? any_rank(*args_.ranks, interrupt_requested()) : interrupt_requested())
                throw StopRun{"interrupted"};
            if (plan_.steps && s.step - first_step >= *plan_.steps) throw StopRun{"completed"};
        };

        totals_.outcome = "completed";
        int code = exit_ok;
        std::string message, signal;
        try {
            try {
                if (resume_) {
                    // The checkpoint's step row, probe samples and frame are on disk already.
                    next_frame = static_cast<std::uint64_t>(std::floor(sim_.time() / plan_.every + 1e-9)) + 1;
                } else {
                    record_.step(sim_.info());
                    sample_probes();
                    submit_frame();
                    // Something to go back to when a device fails.
                    if (args_.on_device_failure == "continue") write_checkpoint_now();
                }
                while (sim_.time() < plan_.until - eps) {
                    const double frame_time = static_cast<double>(next_frame) * plan_.every;
                    sim_.run_until(std::min(frame_time, plan_.until), on_step);
                    if (sim_.time() >= frame_time - eps) {
                        submit_frame();
                        ++next_frame;
                        if (args_.checkpoint_every && sim_.time() >= next_checkpoint_ - eps) {
                            write_checkpoint_now();
                            next_checkpoint_ = (std::floor(sim_.time() / *args_.checkpoint_every + 1e-9) + 1) *
                                               *args_.checkpoint_every;
                        }
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
            // Whenever the run ends whole (completed, --steps, --until, Ctrl-C, SIGTERM): a
            // checkpoint to resume from (clsph resume).
            if (last_checkpoint_step_ != sim_.info().step && !args_.no_checkpoint) write_checkpoint_now();
        } catch (const SimulationError& e) {
            progress_.clear();
            totals_.outcome = "failed";
            message = e.what();
            code = exit_simulation_failed;
            write_last_good();
        } catch (const DeviceError& e) {
            // Across ranks a device fails on one rank only, while the others wait for it in the
            // step: stop every rank now, with this rank's message (mpirun reports the status).
            if (args_.ranks && ranks_in(*args_.ranks) > 1) {
                progress_.clear();
                abort_all(*args_.ranks, exit_device_failed, std::string("error: ") + e.what());
            }
            if (args_.on_device_failure == "continue" && sim_.device_names().size() > 1 && !e.device().empty()) {
                // run_command goes back to the last checkpoint on the devices that are left.
                progress_.clear();
                failed_device_ = e.device();
                failure_message_ = e.what();
                frames_.finish();
                record_.flush();
                return exit_device_failed;
            }
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
        if (!speaks(args_)) return code;  // across ranks, rank 0 reports

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
    // --output-stride, --output-box: what the devices select for a frame.
    Simulation::Selection selection() const {
        Simulation::Selection s;
        s.stride = static_cast<std::uint32_t>(std::min<std::size_t>(args_.output_stride, 0xffffffffu));
        if (args_.output_box.size() == 6)
            s.box = std::array<double, 6>{args_.output_box[0], args_.output_box[1], args_.output_box[2],
                                          args_.output_box[3], args_.output_box[4], args_.output_box[5]};
        return s;
    }

    void submit_frame() {
        if (frames_.pieces())
            frames_.submit_pieces(sim_.time(), after_step("downloading a frame", [&] {
                                      return sim_.particles_by_device(selection());
                                  }));
        else if (!selection().all())  // only the frame's particles come to the host
            frames_.submit(sim_.time(), after_step("downloading a frame", [&] { return sim_.particles(selection()); }));
        else
            frames_.submit(sim_.time(), after_step("downloading a frame", [&] { return sim_.particles(); }));
        if (surfaces_) after_step("extracting the free surface", [&] {
                surfaces_->at_frame(sim_);
                return 0;
            });
        record_.flush();
        arm_abort_record(record_.json_path(), record_.abort_text(sim_.info()));
    }

    // checkpoint_<step>.clsph (through a .tmp and a rename), the oldest beyond --checkpoint-keep removed.
    void write_checkpoint_now() {
        char name[64];
        std::snprintf(name, sizeof name, "checkpoint_%05llu.clsph", static_cast<unsigned long long>(sim_.info().step));
        const std::string path = plan_.out_dir + "/" + name;
        after_step("writing a checkpoint", [&] {
            sim_.save(path);
            return 0;
        });
        last_checkpoint_step_ = sim_.info().step;
        if (!speaks(args_)) return;  // across ranks rank 0 wrote it, and keeps the directory
        const auto all = list_checkpoints(plan_.out_dir);
        for (std::size_t i = 0; i + args_.checkpoint_keep < all.size(); ++i) std::remove(all[i].second.c_str());
    }

    void sample_probes() {
        if (sim_.scene().probes.empty()) return;
        record_.probes(after_step("sampling the probes", [&] { return sim_.sample_probes(); }));
    }

    // The API does not say at what time last_good() was taken (with this loop it is the last frame
    // downloaded), so it goes beside the series rather than into the .pvd at a guessed time.
    void write_last_good() {
        if (!speaks(args_)) return;
        const std::string base = plan_.out_dir + "/last_good";
        write_vtu(base + ".vtu", sim_.last_good());
        if (args_.csv) write_csv(base + ".csv", sim_.last_good());
    }

    Simulation& sim_;
    const RunArgs& args_;
    const RunPlan& plan_;
    const ResumeState* resume_;
    RunRecord record_;
    FrameWriter frames_;
    std::unique_ptr<SurfaceOutput> surfaces_;  // --surface
    Progress progress_;
    RunTotals totals_;
    double next_checkpoint_ = args_.checkpoint_every ? *args_.checkpoint_every : 0.0;
    std::uint64_t last_checkpoint_step_ = ~std::uint64_t{0};
    std::string failed_device_, failure_message_;
};

// The selection spec of `names` (labels "#i ...") without `failed`.
std::string remaining_devices(const std::vector<std::string>& names, const std::string& failed) {
    std::string spec;
    for (const auto& n : names) {
        if (n == failed || n.size() < 2 || n[0] != '#') continue;
        spec += (spec.empty() ? "" : ",") + n.substr(1, n.find(' ') - 1);
    }
    return spec;
}

}  // namespace

// The checks before the first step found the initial state itself out of bounds (a density band
// the hydrostatic start already leaves): a blow-up at step 1, reported as any blow-up is (exit 2,
// run.json "failed", the state at t = 0 the message names in last_good.vtu).
int initial_state_failed(const Scene& scene, const RunArgs& args, const RunPlan& plan, const std::string& message) {
    prepare_output_dir(plan.out_dir, args.force);
    RunRecord record(plan.out_dir, RunIdentity{args.scene_path, args.overrides, args.command_line, {}, {}, scene.to_json(), {}, {}},
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

namespace {


// The newest checkpoint in the directory that reads back whole for this scene; the ones refused
// on the way are named with the reason.
std::pair<std::string, Checkpoint> latest_checkpoint(const std::string& dir, const Scene& scene) {
    const auto all = list_checkpoints(dir);
    std::string refused;
    for (auto it = all.rbegin(); it != all.rend(); ++it) {
        try {
            return {it->second, read_checkpoint(it->second, &scene)};
        } catch (const CheckpointError& e) {
            std::cerr << "clsph: refusing " << e.what() << '\n';
            refused += std::string(refused.empty() ? "" : "; ") + e.what();
        }
    }
    if (all.empty()) throw Error("clsph resume: no checkpoint (checkpoint_NNNNN.clsph) in " + dir);
    throw Error("clsph resume: no usable checkpoint in " + dir + " (" + refused + ")");
}

}  // namespace

int resume_run(const Scene& scene, const RunArgs& args, const RunPlan& plan, clock::time_point start);

// The run; with --on-device-failure continue, a device failure goes back to the last checkpoint
// on the devices that are left (as clsph resume would, recorded in run.json's resumes).
int run_with_failover(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* state,
                      const Scene& scene, clock::time_point start) {
    std::string failed, message;
    std::vector<std::string> names = sim.device_names();
    {
        Runner runner(sim, args, plan, state);
        const int code = runner.run(seconds_since(start));
        if (runner.failed_device().empty()) return code;
        failed = runner.failed_device();
        message = runner.failure_message();
    }
    RunArgs next = args;
    next.devices = remaining_devices(names, failed);
    next.resume_dir = plan.out_dir;
    next.resume_reason = "device " + failed + " failed: " + message;
    next.resume_command_line = args.resume_command_line.empty() ? args.command_line : args.resume_command_line;
    std::cerr << "clsph: device " << failed << " failed: " << message
              << "\nclsph: --on-device-failure continue: going back to the last checkpoint on devices " << next.devices
              << '\n';
    // Tests: the injected fault (CLSPH_TEST_FAULT) was the failure; the devices left run clean.
    ::unsetenv("CLSPH_TEST_FAULT");
    return resume_run(scene, next, plan, start);
}

// clsph resume: the run's command line (main.cpp) over its last checkpoint, in its directory.
int resume_run(const Scene& scene, const RunArgs& args, const RunPlan& plan, clock::time_point start) {
    auto [path, checkpoint] = latest_checkpoint(plan.out_dir, scene);
    ResumeState state;
    state.point = {checkpoint.step, checkpoint.time};
    state.frames = read_pvd(plan.out_dir + "/" + plan.collection_name);
    nlohmann::json old;
    try {
        old = nlohmann::json::parse(read_text_file(plan.out_dir + "/run.json"));
    } catch (const std::exception& e) {
        throw Error("clsph resume: cannot read " + plan.out_dir + "/run.json: " + e.what());
    }
    state.start_time = old.value("start_time", std::string());
    if (old.contains("resumes"))
        for (const auto& r : old.at("resumes")) state.resumes.push_back(r.dump());
    install_interrupt_handler();
    std::unique_ptr<Simulation> simulation = make_simulation(scene, args, &checkpoint);
    Simulation& sim = *simulation;
    const auto names = all_device_names(sim, args);
    nlohmann::json entry{{"command_line", args.resume_command_line}, {"checkpoint", path},
                         {"step", checkpoint.step},   {"time", checkpoint.time},
                         {"devices", names}, {"at", utc_now()}};
    if (!args.resume_reason.empty()) entry["reason"] = args.resume_reason;
    state.resumes.push_back(entry.dump());
    if (speaks(args)) {
        std::cout << "clsph: resuming " << plan.out_dir << " from " << path << " (step " << checkpoint.step << ", t = "
                  << checkpoint.time << " s) on";
        for (const auto& d : names) std::cout << (args.ranks ? "\n  " : " ") << d;
        std::cout << (args.ranks ? "\n  " : ", ") << "to t = " << plan.until << " s" << std::endl;
    }
    return run_with_failover(sim, args, plan, &state, scene, start);
}

namespace {
// What a run across MPI ranks does not do yet (issue 21), refused before anything starts.
RunArgs across_ranks(RunArgs args) {
    if (!args.ranks || ranks_in(*args.ranks) < 2) return args;
    auto refuse = [](const char* what) {
        throw Error(std::string(what) + " is not supported across MPI ranks yet (issue 21); run it in one process");
    };
    if (args.dry_run) refuse("--dry-run");
    if (args.on_device_failure == "continue") refuse("--on-device-failure continue");
    if (args.surface || args.surface_every || args.surface_ply || args.surface_spacing > 0 || args.render || args.video)
        refuse("the free surface and images (--surface, --render, --video)");
    if (args.csv) refuse("--csv");
    return args;
}
}  // namespace

int run_command(const RunArgs& given) {
    const RunArgs args = across_ranks(given);
    if (args.no_checkpoint && args.on_device_failure == "continue")
        throw Error("--no-checkpoint with --on-device-failure continue: going on after a device failure starts from a "
                    "checkpoint; drop one of them");
    const auto start = clock::now();
    const Scene scene = load_scene(args.scene_path, args.overrides);
    const RunPlan plan = make_plan(args, scene);
    if (args.dry_run) return with_scene_path(args, [&] { return dry_run(scene, args, plan); });
    if (!args.resume_dir.empty()) return resume_run(scene, args, plan, start);
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
