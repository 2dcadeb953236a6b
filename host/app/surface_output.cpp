#include "surface_output.hpp"

#include <cstdio>
#include <cstdlib>

namespace clsph::app {

namespace {

void write_image(const std::string& dir, std::size_t count, const Image& image) {
    char name[32];
    std::snprintf(name, sizeof name, "render_%05zu.png", count);
    write_png(dir + "/" + name, image);
}

}  // namespace

SurfaceOutput::SurfaceOutput(std::string dir, double every, bool ply, SurfaceOptions options, bool render, bool meshes,
                             bool writes)
    : dir_(std::move(dir)),
      every_(every),
      ply_(ply),
      options_(options),
      render_(render),
      meshes_(meshes || !render),
      writes_(writes) {
    if (meshes_ && writes_) pvd_.emplace(dir_ + "/surface.pvd");
}

void SurfaceOutput::at_frame(Simulation& sim) {
    const double t = sim.time();
    if (count_ > 0 && every_ > 0 && t < next_ - 1e-9 * every_) return;
    if (meshes_) {
        write(t, sim.surface(options_), sim);
    } else {  // images by splats: no mesh needed
        const Image image = sim.image(camera(sim));  // across ranks every rank draws its slabs
        if (writes_) write_image(dir_, count_, image);
        ++count_;
    }
    if (every_ > 0)
        while (next_ <= t + 1e-9 * every_) next_ += every_;
}

void SurfaceOutput::write(double time, const TriangleMesh& mesh, Simulation& sim) {
    char name[32];
    std::snprintf(name, sizeof name, "surface_%05zu", count_);
    if (writes_) {
        write_vtp(dir_ + "/" + name + ".vtp", mesh);
        if (ply_) write_ply(dir_ + "/" + name + ".ply", mesh);
        if (!pvd_) pvd_.emplace(dir_ + "/surface.pvd");
        pvd_->add(time, std::string(name) + ".vtp");
    }
    if (render_) {  // the mesh at hand when the scene draws surfaces, else the scene's own method
        const CameraView& view = camera(sim);
        const bool surface = sim.scene().render.method == RenderMethod::surface;
        const Image image = surface ? sim.render(mesh, view) : sim.image(view);  // across ranks: collective
        if (writes_) write_image(dir_, count_, image);
    }
    ++count_;
}

std::string SurfaceOutput::make_video() const {
    if (!render_ || count_ == 0) return {};
    if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0)
        return "no video: ffmpeg is not installed (apt-get install ffmpeg); the frames are " + dir_ + "/render_*.png";
    const std::string cmd = "ffmpeg -loglevel error -y -framerate 25 -i '" + dir_ + "/render_%05d.png' -pix_fmt yuv420p " +
                            "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" + dir_ + "/render.mp4'";
    if (std::system(cmd.c_str()) != 0) return "no video: ffmpeg failed (" + cmd + ")";
    return "video: " + dir_ + "/render.mp4";
}

}  // namespace clsph::app
