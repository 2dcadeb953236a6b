// clsph view DIR: the live view's page over a run's output directory (docs/live_view.md): its
// frames, finished or as the run writes them, with a timeline; rendered on any device.
#pragma once
#include <string>

namespace clsph::app {

struct ViewArgs {
    std::string dir;
    std::string devices;
    int port = 8080;
    std::string host = "127.0.0.1";
};

// Serves until Ctrl-C or SIGTERM; 0 then. Throws clsph::Error (exit 1) for a directory that is
// not a run's, holds no frames, or a port in use, before anything is served.
int view_command(const ViewArgs& args);

}  // namespace clsph::app
