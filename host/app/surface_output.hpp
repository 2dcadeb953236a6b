// Free-surface meshes during a run (clsph run --surface): at frames, when a surface is due, the
// mesh (Simulation::surface) as DIR/surface_NNNNN.vtp (and .ply with --surface-ply), listed with
// its time in DIR/surface.pvd, which ParaView opens as a time series beside the particles'.
#pragma once
#include <clsph/io.hpp>
#include <clsph/mesh.hpp>
#include <clsph/render.hpp>
#include <clsph/simulation.hpp>

#include <optional>
#include <string>

namespace clsph::app {

class SurfaceOutput {
public:
    // every: simulated seconds between surfaces (0: at every frame); render: also an image of each
    // surface, DIR/render_NNNNN.png (clsph/render.hpp: Simulation::image, so the scene's
    // render.method applies); meshes false (images only, with the splat method): no surface is
    // computed or written, only the images.
    // writes false: across MPI ranks, a rank other than 0, which takes part in making each surface
    // and image (collectives) but writes nothing (rank 0 writes the whole mesh and the picture).
    SurfaceOutput(std::string dir, double every, bool ply, SurfaceOptions options = {}, bool render = false,
                  bool meshes = true, bool writes = true);
    // Called at each frame; writes a surface when one is due (the first frame always).
    void at_frame(Simulation& sim);
    // Writes the surface of `mesh` at `time` (and its image, rendered by `sim`).
    void write(double time, const TriangleMesh& mesh, Simulation& sim);
    bool meshes() const { return meshes_; }
    // With images: an MP4 of them through ffmpeg when it is installed; returns what happened.
    std::string make_video() const;
    std::size_t written() const { return count_; }
    std::string collection_path() const { return pvd_ ? pvd_->path() : std::string(); }
    const SurfaceOptions& options() const { return options_; }

private:
    std::string dir_;
    double every_;
    bool ply_;
    SurfaceOptions options_;
    bool render_;
    bool meshes_;
    bool writes_;
    std::optional<PvdWriter> pvd_;  // surface.pvd: only when meshes are written
    std::size_t count_ = 0;
    double next_ = 0;
    std::optional<CameraView> camera_;  // the scene's, worked out once (framing reads its meshes)
    const CameraView& camera(const Simulation& sim) {
        if (!camera_) camera_ = camera_for(sim.scene());
        return *camera_;
    }
};

}  // namespace clsph::app
