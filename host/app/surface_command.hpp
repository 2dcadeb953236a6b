// clsph surface OUTDIR: the free surface of every frame of a finished run, afterwards, on any
// device: the scene from OUTDIR/run.json, the particles from each frame listed in the run's .pvd.
#pragma once
#include <string>

namespace clsph::app {

struct SurfaceArgs {
    std::string dir;
    std::string devices;
    double spacing = 0;  // m; 0: dp / 2
    bool ply = false;
    bool render = false;  // clsph render: images too
    bool video = false;   // and an MP4 of them (ffmpeg)
};

int surface_command(const SurfaceArgs& args);

}  // namespace clsph::app
