// The clsph command-line tool: reads the command line and hands it to the command asked for.
//   clsph devices [--devices SPEC]
//   clsph run SCENE [OPTIONS]        (clsph run --help lists the options by topic: run_options.cpp)
//   clsph resume DIR [--until T] [--devices SPEC] [--steps N]
//   clsph surface DIR [--devices SPEC] [--spacing M] [--ply]
//   clsph render DIR [--devices SPEC] [--spacing M] [--video]
//   clsph view DIR [--devices SPEC] [--port PORT] [--serve-host ADDR]
#include "devices_command.hpp"
#include "resume_args.hpp"
#include "run_args.hpp"
#include "run_command.hpp"
#include "run_options.hpp"
#include "surface_command.hpp"
#include "view_command.hpp"

#include <CLI/CLI.hpp>
#include <clsph/build_info.hpp>
#include <clsph/error.hpp>
#include <clsph/ranks.hpp>
#include <clsph/version.hpp>

#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace {
// How many processes the launcher started this one among (mpirun/mpiexec of Open MPI and MPICH,
// PMIx, Slurm's srun); 1 when run alone.
int launched_ranks() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "SLURM_NTASKS"}) {
        const char* v = std::getenv(name);
        if (v && *v) {
            const int n = std::atoi(v);
            if (n > 1) return n;
        }
    }
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph: multi-device SPH fluid simulation on OpenCL"};
    app.set_version_flag("--version", std::string("clsph ") + clsph::version() +
                                          (clsph::built_with_mpi() ? ", with MPI (" + clsph::mpi_library_version() + ")"
                                                                   : ", without MPI"));
    app.require_subcommand(1);

    auto* devices = app.add_subcommand("devices", "list the OpenCL devices clsph can use, in selection order");
    std::string spec;
    devices->add_option("--devices", spec, "show which devices a selection spec picks (all|gpu|cpu|0,2|platform:NAME)");

    auto* surface = app.add_subcommand("surface", "mesh the free surface of every frame of a finished run (surface_NNNNN.vtp, surface.pvd)");
    clsph::app::SurfaceArgs surface_args;
    surface->add_option("dir", surface_args.dir, "the output directory of a clsph run")->required();
    surface->add_option("--devices", surface_args.devices, "devices to use (as clsph run --devices)");
    surface->add_option("--spacing", surface_args.spacing, "sample spacing in m (default: dp/2)")->check(CLI::PositiveNumber);
    surface->add_flag("--ply", surface_args.ply, "also write each surface as binary PLY");
    auto* render = app.add_subcommand("render", "the surface and an image (render_NNNNN.png) of every frame of a finished run");
    clsph::app::SurfaceArgs render_args;
    render_args.render = true;
    render->add_option("dir", render_args.dir, "the output directory of a clsph run")->required();
    render->add_option("--devices", render_args.devices, "devices to use (as clsph run --devices)");
    render->add_option("--spacing", render_args.spacing, "sample spacing in m (default: dp/2)")->check(CLI::PositiveNumber);
    render->add_flag("--video", render_args.video, "and an MP4 of the images, if ffmpeg is installed");

    auto* view = app.add_subcommand("view", "the live view's page over a run's output directory (finished or growing), "
                                            "with a timeline of its frames (docs/live_view.md)");
    clsph::app::ViewArgs view_args;
    view->add_option("dir", view_args.dir, "the output directory of a clsph run")->required();
    view->add_option("--devices", view_args.devices, "devices to render on (as clsph run --devices; any, CPU included)");
    view->add_option("--port", view_args.port, "the port to serve on (default 8080)")->check(CLI::Range(1, 65535));
    view->add_option("--serve-host", view_args.host,
                     "listen on ADDR instead of 127.0.0.1 (no authentication: docs/live_view.md)");

    auto* run = app.add_subcommand("run", "run a scene; frames, stats, probes and run.json go to the output directory");
    clsph::app::RunOptions run_options(*run);

    auto* resume = app.add_subcommand("resume", "go on with a run from the last checkpoint in its output directory, in place");
    std::string resume_dir, resume_devices;
    std::optional<double> resume_until;
    std::optional<std::string> resume_steps;
    resume->add_option("dir", resume_dir, "the output directory of a clsph run with checkpoints")->required();
    resume->add_option("--until", resume_until, "simulated seconds to run to (default: the run's own)");
    resume->add_option("--devices", resume_devices, "devices to go on with (default: the run's own)");
    resume->add_option("--steps", resume_steps, "stop after N more steps")->type_name("N");

    clsph::app::RunArgs run_args;  // run or resume; its ranks, once known, for the errors below
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version end here too (status 0); every mistake on the command line is bad
        // input, exit status 1, like a bad scene.
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "clsph: error: " << e.what() << " (clsph --help, clsph run --help)\n";
        return clsph::app::exit_error;
    }
    try {
        if (*devices) return clsph::app::devices_command(spec);
        if (*surface) return clsph::app::surface_command(surface_args);
        if (*resume) {
            run_args = clsph::app::resume_args(resume_dir, resume_until, resume_devices, resume_steps,
                                               std::vector<std::string>(argv, argv + argc));
            if (launched_ranks() > 1) run_args.ranks = clsph::mpi_ranks(argc, argv);  // as for run, below
            return clsph::app::run_command(run_args);
        }
        if (*render) return clsph::app::surface_command(render_args);
        if (*view) return clsph::app::view_command(view_args);
        if (*run) {
            run_args = run_options.args();
            run_args.command_line.assign(argv, argv + argc);
            // Started by mpirun with several ranks: one run across them (docs/mpi.md).
            if (launched_ranks() > 1) run_args.ranks = clsph::mpi_ranks(argc, argv);
            return clsph::app::run_command(run_args);
        }
    } catch (const clsph::DeviceError& e) {
        // Across ranks the others would wait for this one forever: stop them all, with this message.
        if (run_args.ranks) clsph::abort_all(*run_args.ranks, clsph::app::exit_device_failed, std::string("error: ") + e.what());
        // A device (or its driver) failed while the run was being set up: nothing ran, so there is
        // no output directory; the exit status is that of a device failure.
        std::cerr << "clsph: error: " << e.what() << '\n';
        return clsph::app::exit_device_failed;
    } catch (const clsph::Error& e) {
        if (run_args.ranks) clsph::abort_all(*run_args.ranks, clsph::app::exit_error, std::string("error: ") + e.what());
        std::cerr << "clsph: error: " << e.what() << '\n';
        return clsph::app::exit_error;
    } catch (const std::exception& e) {
        // Not ours (std::bad_alloc, a filesystem error): still a message, never a crash.
        if (run_args.ranks) clsph::abort_all(*run_args.ranks, clsph::app::exit_error, std::string("error: ") + e.what());
        std::cerr << "clsph: error: " << e.what() << '\n';
        return clsph::app::exit_error;
    }
    return 0;
}
