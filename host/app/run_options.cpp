#include "run_options.hpp"

#include <clsph/error.hpp>

#include <cstdint>

namespace clsph::app {
namespace {

std::uint64_t parse_steps(const std::string& text) {
    const bool digits = !text.empty() && text.size() <= 13 && text.find_first_not_of("0123456789") == std::string::npos;
    const std::uint64_t n = digits ? std::stoull(text) : 0;
    if (!digits || n == 0 || n > max_steps)
        throw Error("--steps: expected a whole number of steps from 1 to " + std::to_string(max_steps) + ", got '" +
                    text + "'");
    return n;
}

// --serve's port: a whole number from 1 to 65535.
int parse_port(const std::string& text) {
    const bool digits = !text.empty() && text.size() <= 5 && text.find_first_not_of("0123456789") == std::string::npos;
    const int port = digits ? std::stoi(text) : 0;
    if (port < 1 || port > 65535)
        throw Error("--serve: expected a port number from 1 to 65535, got '" + text + "' (clsph run SCENE --serve [PORT])");
    return port;
}

// The --help groups, in the order they are listed.
const char* const scene_group = "Scene";
const char* const devices_group = "Devices";
const char* const time_group = "Time and steps";
const char* const output_group = "Output";
const char* const surface_group = "Images and surfaces";
const char* const checkpoint_group = "Checkpoints and failures";
const char* const balance_group = "Balance and profiling";
const char* const live_group = "Live view";

void add_scene_options(CLI::App& run, RunArgs& a) {
    run.add_option("scene", a.scene_path, "scene file (JSON; schema in docs/scenes.md)")->required();
    // One KEY=VALUE per --set, so that `--set a=1 scene.json` still finds the scene.
    run.add_option("--set", a.overrides, "override a scene key, e.g. --set physics.dp=0.01 (repeatable; default: none)")
        ->allow_extra_args(false)
        ->type_name("KEY=VALUE")
        ->group(scene_group);
    run.add_flag("--dry-run", a.dry_run,
                 "print particle counts, memory per device, first time step and output size, then exit (default: off)")
        ->group(scene_group);
}

void add_device_options(CLI::App& run, RunArgs& a) {
    run.add_option("--devices", a.devices,
                   "devices to use: all|gpu|cpu|default|0,2|platform:NAME, or per MPI rank 'rank0=gpu;*=default' "
                   "(default: $CLSPH_DEVICES, else every GPU, else every CPU)")
        ->group(devices_group);
    run.add_option("--interaction", a.interaction,
                   "interaction form on every device: auto (lanes on pocl CPUs, fine on GPUs and rusticl), fine, lanes, coarse, "
                   "clusters (default: the scene's run.interaction)")
        ->check(CLI::IsMember({"auto", "fine", "lanes", "coarse", "clusters"}))
        ->type_name("NAME")
        ->group(devices_group);
    run.add_option("--cell-order", a.cell_order,
                   "order of the particles within each cell: auto (morton where every device runs lanes), "
                   "arrival, morton (default: the scene's run.cell_order)")
        ->check(CLI::IsMember({"auto", "arrival", "morton"}))
        ->type_name("NAME")
        ->group(devices_group);
    run.add_flag("--synchronous", a.synchronous,
                 "wait for every step on the host (the step ahead off: dt, cell count and statistics read back per step; "
                 "default: off)")
        ->group(devices_group);
}

void add_time_options(CLI::App& run, RunArgs& a, std::optional<std::string>& steps) {
    run.add_option("--until", a.until, "simulated seconds to run to (default: the scene's run.end_time)")->group(time_group);
    run.add_option("--steps", steps, "stop after N steps (alone: run exactly N steps; default: no limit)")
        ->type_name("N")
        ->group(time_group);
    run.add_option("--every", a.every, "simulated seconds between frames (default: the scene's run.output_every)")
        ->group(time_group);
}

void add_output_options(CLI::App& run, RunArgs& a) {
    run.add_option("--out", a.out, "output directory (default: out/<scene file name>)")->group(output_group);
    run.add_flag("--force", a.force, "overwrite the run files in an existing output directory (default: off, refused)")
        ->group(output_group);
    run.add_flag("--csv", a.csv, "also write every frame as CSV (id,type,x,y,z,vx,vy,vz,rho,p; default: off)")
        ->group(output_group);
    run.add_option("--output-stride", a.output_stride, "frames (and CSV) hold every K-th particle by id (default 1: all)")
        ->type_name("K")
        ->group(output_group);
    run.add_option("--fields", a.fields,
                   "the point data frames (and CSV) hold: all, or a list of id,type,velocity,density,pressure (positions "
                   "always; default: all)")
        ->type_name("LIST")
        ->group(output_group);
    run.add_option("--output-box", a.output_box,
                   "frames (and CSV) hold only the particles inside this box (default: the whole domain)")
        ->expected(6)
        ->type_name("XMIN YMIN ZMIN XMAX YMAX ZMAX")
        ->group(output_group);
    run.add_flag("--compress", a.compress,
                 "write frames zlib-compressed (vtkZLibDataCompressor, as ParaView reads them): smaller, slower to write "
                 "(default: off)")
        ->group(output_group);
    run.add_flag("--pieces", a.pieces,
                 "write each frame as one VTU per device (frame_NNNNN_pK.vtu) and an index frame_NNNNN.pvtu, in parallel "
                 "(default: off, one VTU per frame)")
        ->group(output_group);
}

void add_surface_options(CLI::App& run, RunArgs& a) {
    run.add_flag("--surface", a.surface,
                 "write the free surface at every frame: surface_NNNNN.vtp, listed in surface.pvd (default: off)")
        ->group(surface_group);
    run.add_option("--surface-every", a.surface_every,
                   "the free surface every DT simulated seconds, at the frames (implies --surface; default: every frame)")
        ->check(CLI::PositiveNumber)
        ->type_name("DT")
        ->group(surface_group);
    run.add_flag("--surface-ply", a.surface_ply, "also write each surface as binary PLY (implies --surface; default: off)")
        ->group(surface_group);
    run.add_option("--surface-spacing", a.surface_spacing, "the surface's sample spacing in m (default: dp/2; implies --surface)")
        ->check(CLI::PositiveNumber)
        ->type_name("M")
        ->group(surface_group);
    run.add_flag("--render", a.render,
                 "an image at every surface: render_NNNNN.png (implies --surface with the surface method; default: off)")
        ->group(surface_group);
    run.add_option("--render-method", a.render_method,
                   "how images draw the water: surface (the mesh rasterised) or splat (particles as spheres, shaded in "
                   "screen space; no mesh) (default: the scene's render.method)")
        ->check(CLI::IsMember({"surface", "splat"}))
        ->type_name("NAME")
        ->group(surface_group);
    run.add_flag("--video", a.video,
                 "and an MP4 of the images at the end, if ffmpeg is installed (implies --render; default: off)")
        ->group(surface_group);
}

void add_checkpoint_options(CLI::App& run, RunArgs& a) {
    auto* checkpoint_every = run.add_option("--checkpoint-every", a.checkpoint_every,
                                            "write a checkpoint (checkpoint_NNNNN.clsph, docs/checkpoint.md) at the first "
                                            "frame after every DT simulated seconds; one is written whenever the run ends "
                                            "(default: only then)")
                                 ->check(CLI::PositiveNumber)
                                 ->type_name("DT")
                                 ->group(checkpoint_group);
    auto* no_checkpoint = run.add_flag("--no-checkpoint", a.no_checkpoint,
                                       "write no checkpoint, not even at the end (a run whose state would not fit its disk: "
                                       "a checkpoint holds every particle, 52 B each); clsph resume then cannot go on "
                                       "(default: off)")
                              ->group(checkpoint_group);
    no_checkpoint->excludes(checkpoint_every);
    run.add_option("--checkpoint-keep", a.checkpoint_keep, "the last K checkpoints are kept (default 3)")
        ->check(CLI::PositiveNumber)
        ->type_name("K")
        ->group(checkpoint_group);
    run.add_option("--on-device-failure", a.on_device_failure,
                   "when a device fails mid-run: stop (exit 3, last_good.vtu) or continue (back to the last checkpoint, "
                   "the slabs re-cut over the remaining devices, across MPI ranks those of every rank; default: stop)")
        ->check(CLI::IsMember({"stop", "continue"}))
        ->group(checkpoint_group);
}

void add_balance_options(CLI::App& run, RunArgs& a) {
    run.add_option("--balance", a.balance,
                   "several devices: cuts follow measured times every step (dynamic), are set once by equal work (static), "
                   "or are equal widths (off); default: dynamic")
        ->check(CLI::IsMember({"dynamic", "static", "off"}))
        ->group(balance_group);
    run.add_option("--balance-log", a.balance_log,
                   "several devices: write the balancer's per-step CSV to FILE (docs/balance.md; default: none)")
        ->type_name("FILE")
        ->group(balance_group);
    run.add_flag("--profile", a.profile, "time every kernel and print a per-kernel table at the end (default: off)")
        ->group(balance_group);
}

void add_live_options(CLI::App& run, RunArgs& a, std::optional<std::string>& serve) {
    auto* serve_option = run.add_option("--serve", serve,
                   "watch the run in a browser: serve a live view on PORT of this machine (127.0.0.1), with pause, "
                   "step, orbit and probe plots; reach it from elsewhere with ssh -L PORT:localhost:PORT "
                   "(docs/live_view.md; steps then wait for the host, as --synchronous; default: off, PORT 8080)")
        ->expected(0, 1)
        ->default_str("8080")
        ->type_name("[PORT]")
        ->group(live_group);
    run.add_option("--serve-host", a.serve_host,
                   "the address the live view listens on, e.g. 0.0.0.0 for every interface: anyone who reaches it can "
                   "pause the run and write files, without a password (default: 127.0.0.1)")
        ->type_name("ADDR")
        ->needs(serve_option)
        ->group(live_group);
}

}  // namespace

RunOptions::RunOptions(CLI::App& run) {
    add_scene_options(run, args_);
    add_device_options(run, args_);
    add_time_options(run, args_, steps_);
    add_output_options(run, args_);
    add_surface_options(run, args_);
    add_checkpoint_options(run, args_);
    add_balance_options(run, args_);
    add_live_options(run, args_, serve_);
    run.footer(
        "MPI:\n"
        "  Started by mpirun, mpiexec or srun with several ranks, one run spans them: each rank drives its\n"
        "  share of the devices (--devices) and its run of the slabs; rank 0 writes the run's files, every\n"
        "  rank its frame pieces (docs/mpi.md).");
}

RunArgs RunOptions::args() const {
    RunArgs a = args_;
    if (steps_) a.steps = parse_steps(*steps_);
    if (serve_) a.serve = parse_port(*serve_);
    return a;
}

}  // namespace clsph::app
