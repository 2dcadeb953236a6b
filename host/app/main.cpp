// The clsph command-line tool. It uses only the public API (host/include/clsph).
//   clsph devices [--devices SPEC]
//   clsph run SCENE [--devices SPEC] [--until T] [--steps N] [--out DIR] [--every DT] [--csv]
//                   [--profile] [--set KEY=VALUE]... [--dry-run] [--force] [--interaction NAME]
//                   [--balance dynamic|static|off] [--balance-log FILE] [--surface] [--surface-every DT]
//                   [--surface-ply] [--checkpoint-every DT] [--checkpoint-keep K]
//                   [--on-device-failure stop|continue] [--compress] [--pieces]
//   clsph resume DIR [--until T] [--devices SPEC] [--steps N]
//   clsph surface DIR [--devices SPEC] [--spacing M] [--ply]
//   clsph render DIR [--devices SPEC] [--spacing M] [--video]
#include "run_args.hpp"
#include "run_command.hpp"
#include "surface_command.hpp"

#include <CLI/CLI.hpp>
#include <clsph/build_info.hpp>
#include <clsph/devices.hpp>
#include <clsph/error.hpp>
#include <clsph/ranks.hpp>
#include <clsph/version.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace {

int list_devices_command(const std::string& spec) {
    const auto all = clsph::list_devices();
    std::cout << clsph::format_device_table(all);
    const std::string used = spec.empty() ? clsph::default_device_spec() : spec;
    const auto chosen = clsph::select_devices(all, used);
    std::cout << "selection '" << used << "' picks:";
    for (auto i : chosen) std::cout << ' ' << i;
    std::cout << '\n';
    return 0;
}

std::optional<std::string> steps_text;

std::uint64_t parse_steps(const std::string& text) {
    const bool digits = !text.empty() && text.size() <= 13 && text.find_first_not_of("0123456789") == std::string::npos;
    const std::uint64_t n = digits ? std::stoull(text) : 0;
    if (!digits || n == 0 || n > clsph::app::max_steps)
        throw clsph::Error("--steps: expected a whole number of steps from 1 to " + std::to_string(clsph::app::max_steps) +
                           ", got '" + text + "'");
    return n;
}

void add_run_options(CLI::App& run, clsph::app::RunArgs& a) {
    run.add_option("scene", a.scene_path, "scene file (JSON; schema in docs/scenes.md)")->required();
    run.add_option("--devices", a.devices, "devices to use: all|gpu|cpu|default|0,2|platform:NAME (default: $CLSPH_DEVICES, else every GPU, else every CPU)");
    run.add_option("--until", a.until, "simulated seconds to run to (default: the scene's run.end_time)");
    // Read as text and checked here: a negative or enormous count is an error, never wrapped around.
    run.add_option("--steps", steps_text, "stop after N steps (alone: run exactly N steps)")->type_name("N");
    run.add_option("--out", a.out, "output directory (default: out/<scene file name>)");
    run.add_option("--every", a.every, "simulated seconds between frames (default: the scene's run.output_every)");
    run.add_flag("--csv", a.csv, "also write every frame as CSV (id,type,x,y,z,vx,vy,vz,rho,p)");
    run.add_option("--output-stride", a.output_stride, "frames (and CSV) hold every K-th particle by id (default 1: all)")
        ->type_name("K");
    run.add_option("--fields", a.fields, "the point data frames (and CSV) hold: all, or a list of id,type,velocity,density,pressure (positions always)")
        ->type_name("LIST");
    run.add_option("--output-box", a.output_box, "frames (and CSV) hold only the particles inside this box")
        ->expected(6)
        ->type_name("XMIN YMIN ZMIN XMAX YMAX ZMAX");
    run.add_flag("--compress", a.compress,
                 "write frames zlib-compressed (vtkZLibDataCompressor, as ParaView reads them): smaller, slower to write");
    run.add_flag("--pieces", a.pieces,
                 "write each frame as one VTU per device (frame_NNNNN_pK.vtu) and an index frame_NNNNN.pvtu, in parallel");
    run.add_flag("--profile", a.profile, "time every kernel and print a per-kernel table at the end");
    run.add_flag("--synchronous", a.synchronous,
                 "wait for every step on the host (the step ahead off: dt, cell count and statistics read back per step)");
    // One KEY=VALUE per --set, so that `--set a=1 scene.json` still finds the scene.
    run.add_option("--set", a.overrides, "override a scene key, e.g. --set physics.dp=0.01 (repeatable)")
        ->allow_extra_args(false)
        ->type_name("KEY=VALUE");
    run.add_flag("--dry-run", a.dry_run, "print particle counts, memory per device, first time step and output size, then exit");
    run.add_flag("--force", a.force, "overwrite the run files in an existing output directory");
    run.add_option("--interaction", a.interaction,
                   "interaction form on every device: auto (lanes on pocl CPUs, fine on GPUs and rusticl), fine, lanes, coarse "
                   "(default: the scene's run.interaction)")
        ->check(CLI::IsMember({"auto", "fine", "lanes", "coarse"}))
        ->type_name("NAME");
    run.add_flag("--surface", a.surface, "write the free surface at every frame: surface_NNNNN.vtp, listed in surface.pvd");
    run.add_option("--surface-every", a.surface_every, "the free surface every DT simulated seconds, at the frames (implies --surface)")
        ->check(CLI::PositiveNumber)
        ->type_name("DT");
    run.add_flag("--surface-ply", a.surface_ply, "also write each surface as binary PLY (implies --surface)");
    run.add_flag("--render", a.render, "an image of the surface at every surface: render_NNNNN.png (implies --surface)");
    run.add_flag("--video", a.video, "and an MP4 of the images at the end, if ffmpeg is installed (implies --render)");
    run.add_option("--surface-spacing", a.surface_spacing, "the surface's sample spacing in m (default: dp/2; implies --surface)")
        ->check(CLI::PositiveNumber)
        ->type_name("M");
    run.add_option("--balance", a.balance, "several devices: cuts follow measured times every step (dynamic), are set once by equal work (static), or are equal widths (off)")
        ->check(CLI::IsMember({"dynamic", "static", "off"}))
        ->capture_default_str();
    auto* checkpoint_every = run.add_option("--checkpoint-every", a.checkpoint_every,
                   "write a checkpoint (checkpoint_NNNNN.clsph, docs/checkpoint.md) at the first frame after every DT "
                   "simulated seconds; one is written whenever the run ends")
        ->check(CLI::PositiveNumber)
        ->type_name("DT");
    auto* no_checkpoint = run.add_flag("--no-checkpoint", a.no_checkpoint,
                                       "write no checkpoint, not even at the end (a run whose state would not fit its disk: "
                                       "a checkpoint holds every particle, 52 B each); clsph resume then cannot go on");
    no_checkpoint->excludes(checkpoint_every);
    run.add_option("--checkpoint-keep", a.checkpoint_keep, "the last K checkpoints are kept (default 3)")
        ->check(CLI::PositiveNumber)
        ->type_name("K");
    run.add_option("--on-device-failure", a.on_device_failure,
                   "when a device fails mid-run: stop (exit 3, last_good.vtu) or continue (back to the last checkpoint, "
                   "the slabs re-cut over the remaining devices)")
        ->check(CLI::IsMember({"stop", "continue"}))
        ->capture_default_str();
    run.add_option("--balance-log", a.balance_log, "several devices: write the balancer's per-step CSV to FILE (docs/balance.md)")
        ->type_name("FILE");
}

// clsph resume DIR: the command line in DIR/run.json with --out DIR and the resume's own
// --until, --devices and --steps in place of the original's, parsed as `clsph run` parses it.
clsph::app::RunArgs resume_args(const std::string& dir, const std::optional<double>& until, const std::string& devices,
                                const std::optional<std::string>& steps, const std::vector<std::string>& own_argv) {
    std::ifstream f(dir + "/run.json");
    if (!f) throw clsph::Error("clsph resume: no run.json in " + dir + " (not the output directory of a clsph run)");
    std::vector<std::string> original;
    try {
        original = nlohmann::json::parse(f).at("command_line").get<std::vector<std::string>>();
    } catch (const std::exception& e) {
        throw clsph::Error("clsph resume: cannot read the command line from " + dir + "/run.json: " + e.what());
    }
    const auto run_at = std::find(original.begin(), original.end(), "run");
    if (run_at == original.end()) throw clsph::Error("clsph resume: " + dir + "/run.json records no `clsph run` command line");
    // Dropped with their values: what the resume sets itself, and what only a fresh start means.
    std::vector<std::string> with_value = {"--out"};
    if (until) with_value.push_back("--until");
    if (!devices.empty()) with_value.push_back("--devices");
    if (steps) with_value.push_back("--steps");
    const std::vector<std::string> flags = {"--force", "--dry-run"};
    std::vector<std::string> argv;
    for (auto it = run_at + 1; it != original.end(); ++it) {
        const std::string& a = *it;
        const std::string name = a.substr(0, a.find('='));
        if (std::find(flags.begin(), flags.end(), a) != flags.end()) continue;
        if (std::find(with_value.begin(), with_value.end(), name) != with_value.end()) {
            if (a.find('=') == std::string::npos && it + 1 != original.end()) ++it;
            continue;
        }
        argv.push_back(a);
    }
    if (until) argv.insert(argv.end(), {"--until", std::to_string(*until)});
    if (!devices.empty()) argv.insert(argv.end(), {"--devices", devices});
    if (steps) argv.insert(argv.end(), {"--steps", *steps});
    argv.insert(argv.end(), {"--out", dir});
    CLI::App app{"clsph resume"};
    auto* run = app.add_subcommand("run");
    clsph::app::RunArgs a;
    steps_text.reset();
    add_run_options(*run, a);
    std::vector<std::string> reversed{"run"};
    reversed.insert(reversed.end(), argv.begin(), argv.end());
    std::reverse(reversed.begin(), reversed.end());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw clsph::Error(std::string("clsph resume: the recorded command line does not parse: ") + e.what());
    }
    if (steps_text) a.steps = parse_steps(*steps_text);
    a.command_line.assign(original.begin(), original.end());
    a.resume_dir = dir;
    a.resume_command_line = own_argv;
    return a;
}

}  // namespace

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

    auto* run = app.add_subcommand("run", "run a scene; frames, stats, probes and run.json go to the output directory");
    clsph::app::RunArgs run_args;
    add_run_options(*run, run_args);

    auto* resume = app.add_subcommand("resume", "go on with a run from the last checkpoint in its output directory, in place");
    std::string resume_dir, resume_devices;
    std::optional<double> resume_until;
    std::optional<std::string> resume_steps;
    resume->add_option("dir", resume_dir, "the output directory of a clsph run with checkpoints")->required();
    resume->add_option("--until", resume_until, "simulated seconds to run to (default: the run's own)");
    resume->add_option("--devices", resume_devices, "devices to go on with (default: the run's own)");
    resume->add_option("--steps", resume_steps, "stop after N more steps")->type_name("N");

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
        if (steps_text) run_args.steps = parse_steps(*steps_text);
        if (*devices) return list_devices_command(spec);
        if (*surface) return clsph::app::surface_command(surface_args);
        if (*resume) {
            run_args = resume_args(resume_dir, resume_until, resume_devices, resume_steps,
                                   std::vector<std::string>(argv, argv + argc));
            if (launched_ranks() > 1) run_args.ranks = clsph::mpi_ranks(argc, argv);  // as for run, below
            return clsph::app::run_command(run_args);
        }
        if (*render) return clsph::app::surface_command(render_args);
        if (*run) {
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
