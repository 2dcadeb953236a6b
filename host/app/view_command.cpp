#include "view_command.hpp"

#include "interrupt.hpp"
#include "run_dir.hpp"
#include "serve/view_server.hpp"

#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/render.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <thread>

namespace clsph::app {

int view_command(const ViewArgs& args) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(args.dir, ec)) throw Error("clsph view: " + args.dir + " is not a directory (the output directory of clsph run)");
    const Scene scene = scene_of_run(args.dir, "clsph view");
    const std::string pvd = frames_pvd(args.dir);
    if (pvd.empty()) throw Error("clsph view: no frame collection (.pvd) in " + args.dir + ": the run has written no frame (yet)");
    if (read_pvd(pvd).empty()) throw Error("clsph view: " + pvd + " lists no frame");
    Options options;
    options.devices = args.devices;
    serve::FrameSource source(args.dir, pvd, scene, options);
    const Vec3 lo = scene.domain.min, hi = scene.domain.max;
    const double size = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    install_interrupt_handler();
    serve::ViewServer server(serve::ServeAddress{args.host, args.port}, source, camera_for(scene), size);
    std::cout << "clsph: viewing " << args.dir << " at " << server.url();
    if (serve::is_loopback(args.host))
        std::cout << " (this machine only; from another: ssh -L " << args.port << ":localhost:" << args.port
                  << " THIS_HOST, then http://localhost:" << args.port << "/)\n";
    else
        std::cout << "\nclsph: warning: --serve-host " << args.host
                  << ": the view is open to the network, without authentication (docs/live_view.md)\n";
    std::cout << "clsph: Ctrl-C to stop\n" << std::flush;
    while (!interrupt_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::cout << "clsph: view stopped (" << signal_name(interrupt_signal()) << ")\n";
    return 0;
}

}  // namespace clsph::app
