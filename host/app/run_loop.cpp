#include "run_loop.hpp"

#include "frame_writer.hpp"
#include "interrupt.hpp"
#include "output_dir.hpp"
#include "progress.hpp"
#include "report.hpp"
#include "run_ranks.hpp"
#include "serve/live_view.hpp"
#include "surface_output.hpp"

#include <clsph/error.hpp>
#include <clsph/ranks.hpp>

#include <unistd.h>  // isatty

#include <algorithm>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <sstream>

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
    Runner(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* resume = nullptr)
        : sim_(sim),
          args_(args),
          plan_(plan),
          resume_(resume),
          record_(plan.out_dir,
                  RunIdentity{args.scene_path, args.overrides, args.command_line, all_device_names(sim, args),
                              interaction_forms(sim), cell_order_name(sim.cell_order()), sim.scene().to_json(), resume ? resume->start_time : std::string(),
                              resume ? resume->resumes : std::vector<std::string>{}},
                  sim.scene().probes, resume ? &resume->point : nullptr, speaks(args)),
          filter_(FrameFilter::from_options(args.output_stride, args.output_box, args.fields)),
          frames_(plan.out_dir, plan.collection_name, FrameFormat{args.csv, args.compress, args.pieces, args.ranks.get()},
                  filter_),
          surfaces_(args.wants_surface()
                        ? std::make_unique<SurfaceOutput>(plan.out_dir, args.surface_every.value_or(0.0), args.surface_ply,
                                                          SurfaceOptions{args.surface_spacing, 0.5}, args.render || args.video,
                                                          args.wants_meshes() ||
                                                              sim.scene().render.method == RenderMethod::surface,
                                                          speaks(args))
                        : nullptr),
          progress_(sim.time(), plan.until, plan.steps, isatty(STDERR_FILENO) != 0) {
        if (resume_) {
            frames_.resume_at(resume_->frames, resume_->point.time);
            last_checkpoint_step_ = resume_->point.step;
            if (args_.checkpoint_every) next_checkpoint_ = next_checkpoint_after(sim.time());
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
        first_ahead_ = sim_.steps_taken_ahead();
        first_thrown_ = sim_.steps_thrown_ahead();
        std::uint64_t next_frame = 1;
        const double eps = 1e-9 * plan_.every;

        auto on_step = [&](const StepInfo& s) {
            record_.step(s);
            record_.bodies(sim_.bodies());  // floating bodies: a row each step
            totals_.particle_steps += static_cast<double>(s.particles);
            const int every = sim_.scene().run.probe_every;
            if (every > 0 && s.step % static_cast<std::uint64_t>(every) == 0) sample_probes();
            if (speaks(args_)) progress_.update(s, sim_);
            frames_.check();  // a writer error (disk full) ends the run now, not at the end
            // --serve: images, the page's requests, and a pause, all between two steps.
            if (args_.live) args_.live->between_steps(sim_, live_hooks_);
            // Across ranks every rank stops at the same step, whichever got the signal.
            if (args_.ranks ? any_rank(*args_.ranks, interrupt_requested()) : interrupt_requested())
                throw StopRun{"interrupted"};
            if (plan_.steps && s.step - first_step >= *plan_.steps) throw StopRun{"completed"};
        };

        totals_.outcome = "completed";
        // --serve: the page hears how the run ended, however it ends (images are refused from then).
        struct TellLiveView {
            serve::LiveView* view;
            const std::string& outcome;
            ~TellLiveView() {
                if (view) view->finished(outcome);
            }
        } tell_live_view{args_.live.get(), totals_.outcome};
        int code = exit_ok;
        std::string message, signal;
        try {
            try {
                if (resume_) {
                    // The checkpoint's step row, probe samples and frame are on disk already.
                    next_frame = static_cast<std::uint64_t>(std::floor(sim_.time() / plan_.every + 1e-9)) + 1;
                } else {
                    record_.step(sim_.info());
                    record_.bodies(sim_.bodies());
                    sample_probes();
                    submit_frame();
                    // Something to go back to when a device fails.
                    if (args_.on_device_failure == "continue") write_checkpoint_now();
                }
                if (args_.live) args_.live->started(sim_.info());
                while (sim_.time() < plan_.until - eps) {
                    const double frame_time = static_cast<double>(next_frame) * plan_.every;
                    sim_.run_until(std::min(frame_time, plan_.until), on_step);
                    if (sim_.time() >= frame_time - eps) {
                        submit_frame();
                        ++next_frame;
                        if (args_.checkpoint_every && sim_.time() >= next_checkpoint_ - eps) {
                            write_checkpoint_now();
                            next_checkpoint_ = next_checkpoint_after(sim_.time());
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
            const bool across = args_.ranks && ranks_in(*args_.ranks) > 1;
            if (across && args_.on_device_failure == "continue" && !e.device().empty()) {
                // The others, waiting for this rank inside the step, give it up too; every rank
                // then goes back to the last checkpoint on the devices left (resume.cpp).
                give_up(*args_.ranks, e.what());
                return hand_over(e.device(), e.what());
            }
            // Across ranks a device fails on one rank only, while the others wait for it in the
            // step: stop every rank now, with this rank's message (mpirun reports the status).
            if (across) {
                progress_.clear();
                abort_all(*args_.ranks, exit_device_failed, std::string("error: ") + e.what());
            }
            if (args_.on_device_failure == "continue" && sim_.device_names().size() > 1 && !e.device().empty())
                return hand_over(e.device(), e.what());  // the failover (resume.cpp): the devices left
            // A device failed mid-run (lost, out of resources): its state is gone; the last frame
            // downloaded is written as the last good state.
            progress_.clear();
            totals_.outcome = "failed";
            message = e.what();
            code = exit_device_failed;
            write_last_good();
        } catch (const RankFailure& e) {
            // Another rank gave up the step (its device failed) and this one gave up its own.
            if (args_.on_device_failure == "continue") return hand_over({}, e.what());
            progress_.clear();  // that rank stops every rank; should this one be first, the same message
            abort_all(*args_.ranks, exit_device_failed, std::string("error: ") + e.what());
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
        frames_.finish();
        totals_.loop_seconds = seconds_since(start);
        if (sim_.scene().run.list_buffer > 0) record_.table_builds(sim_.table_builds().builds);
        record_.steps_ahead(sim_.steps_taken_ahead() - first_ahead_, sim_.steps_thrown_ahead() - first_thrown_);
        record_.finish(totals_.outcome, sim_.info(), message, code, signal);
        disarm_abort_record();
        if (speaks(args_)) report(code, message, first_step);  // across ranks, rank 0 reports
        return code;
    }

private:
    // A device failed (here: its label; across ranks empty where another rank's did) and the run
    // goes on from its last checkpoint: what is written so far stays, the failover takes over.
    int hand_over(const std::string& device, const std::string& message) {
        progress_.clear();
        failed_device_ = device;
        failure_message_ = message;
        frames_.finish();
        record_.flush();
        return exit_device_failed;
    }

    // The summary on the terminal; on a failure the error is the last thing said.
    void report(int code, const std::string& message, std::uint64_t first_step) {
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
                                      "), interaction " + interaction_name(d.interaction) + ", cells in " +
                                      cell_order_name(d.cell_order) + " order");
        }
        totals_.list_buffer = sim_.scene().run.list_buffer;
        totals_.table_builds = sim_.table_builds().builds;
        totals_.steps_ahead = sim_.steps_taken_ahead() - first_ahead_;
        totals_.steps_thrown = sim_.steps_thrown_ahead() - first_thrown_;
        print_summary(std::cout, totals_);
        if (surfaces_ && surfaces_->written() > 0) {
            if (surfaces_->meshes())
                std::cout << "  surfaces: " << surfaces_->written() << " in " << surfaces_->collection_path() << '\n';
            else
                std::cout << "  images: " << surfaces_->written() << " (render_NNNNN.png, splats: no surface meshes)\n";
            if (args_.video) std::cout << "  " << surfaces_->make_video() << '\n';
        }
        if (args_.profile && code != exit_device_failed) {
            print_profile(std::cout, sim_.profile(), totals_.steps, sim_.device_names().size());
            for (const auto& d : sim_.shares())  // which form the sph.forces (and sph.density) rows ran
                std::cout << "  interaction form on " << d.device << ": " << interaction_name(d.interaction) << '\n';
        }
        if (code == exit_simulation_failed || code == exit_device_failed) {
            std::cout.flush();
            std::cerr << "clsph: error: " << message << "\nclsph: the last good state is in " << plan_.out_dir
                      << "/last_good.vtu\n";
        }
    }

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
        const Simulation::Selection selection = filter_.device_selection();
        if (frames_.pieces())
            frames_.submit_pieces(sim_.time(), after_step("downloading a frame", [&] {
                                      return sim_.particles_by_device(selection);
                                  }));
        else if (!selection.all())  // only the frame's particles come to the host
            frames_.submit(sim_.time(), after_step("downloading a frame", [&] { return sim_.particles(selection); }));
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
        const std::string path = checkpoint_path(plan_.out_dir, sim_.info().step);
        after_step("writing a checkpoint", [&] {
            sim_.save(path);
            return 0;
        });
        last_checkpoint_step_ = sim_.info().step;
        // Across ranks rank 0 wrote it, and keeps the directory.
        if (speaks(args_)) remove_old_checkpoints(plan_.out_dir, args_.checkpoint_keep);
    }

    // --checkpoint-every DT: the first multiple of DT after `time`.
    double next_checkpoint_after(double time) const {
        return (std::floor(time / *args_.checkpoint_every + 1e-9) + 1) * *args_.checkpoint_every;
    }

    void sample_probes() {
        if (sim_.scene().probes.empty()) return;
        const auto samples = after_step("sampling the probes", [&] { return sim_.sample_probes(); });
        record_.probes(samples);
        if (args_.live) args_.live->probes(samples);
    }

    // The live view's "write now": a frame and a checkpoint of the state now, by the run's own
    // writers (none twice at one step); says what it wrote, in the page's words.
    std::string write_now() {
        std::ostringstream said;
        const double eps = 1e-9 * plan_.every;
        if (frames_.last_time() < sim_.time() - eps) {
            submit_frame();
            said << "frame " << frames_.frames_written() << " at t = " << sim_.time() << " s";
        } else {
            said << "the frame at t = " << sim_.time() << " s was written already";
        }
        if (args_.no_checkpoint) {
            said << "; no checkpoint (--no-checkpoint)";
        } else if (last_checkpoint_step_ != sim_.info().step) {
            write_checkpoint_now();
            said << "; " << checkpoint_path(plan_.out_dir, sim_.info().step);
        }
        return said.str();
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
    FrameFilter filter_;  // --output-stride, --output-box, --fields
    FrameWriter frames_;
    std::unique_ptr<SurfaceOutput> surfaces_;  // --surface
    Progress progress_;
    RunTotals totals_;
    double next_checkpoint_ = args_.checkpoint_every ? *args_.checkpoint_every : 0.0;
    std::uint64_t last_checkpoint_step_ = ~std::uint64_t{0};
    std::string failed_device_, failure_message_;
    std::uint64_t first_ahead_ = 0, first_thrown_ = 0;  // steps_taken/thrown_ahead() when run() began
    const serve::RunHooks live_hooks_{[this] { return write_now(); }, [] { return interrupt_requested(); }};
};

}  // namespace

LoopEnd run_loop(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* resume,
                 std::chrono::steady_clock::time_point start) {
    Runner runner(sim, args, plan, resume);
    LoopEnd end;
    end.code = runner.run(seconds_since(start));
    end.failed_device = runner.failed_device();
    end.failure_message = runner.failure_message();
    return end;
}

}  // namespace clsph::app
