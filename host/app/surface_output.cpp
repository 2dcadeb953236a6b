#include "surface_output.hpp"

#include <cstdio>

namespace clsph::app {

SurfaceOutput::SurfaceOutput(std::string dir, double every, bool ply, SurfaceOptions options)
    : dir_(std::move(dir)), every_(every), ply_(ply), options_(options), pvd_(dir_ + "/surface.pvd") {}

void SurfaceOutput::at_frame(Simulation& sim) {
    const double t = sim.time();
    if (count_ > 0 && every_ > 0 && t < next_ - 1e-9 * every_) return;
    write(t, sim.surface(options_));
    if (every_ > 0)
        while (next_ <= t + 1e-9 * every_) next_ += every_;
}

void SurfaceOutput::write(double time, const TriangleMesh& mesh) {
    char name[32];
    std::snprintf(name, sizeof name, "surface_%05zu", count_);
    write_vtp(dir_ + "/" + name + ".vtp", mesh);
    if (ply_) write_ply(dir_ + "/" + name + ".ply", mesh);
    pvd_.add(time, std::string(name) + ".vtp");
    ++count_;
}

}  // namespace clsph::app
