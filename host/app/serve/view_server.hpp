// clsph view DIR: the live view's page over a run's output directory (finished, or growing while
// the run goes on): the frames its .pvd lists, each rendered on request by a Simulation built from
// the frame's particles (on any OpenCL device, CPU included), with a timeline to scrub them. The
// rendering is on the server's threads, one image at a time; nothing else runs in the process.
#pragma once
#include "http_common.hpp"

#include <clsph/io.hpp>
#include <clsph/scene.hpp>
#include <clsph/simulation.hpp>

#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace httplib {
class Server;
}

namespace clsph::app::serve {

// The frames of an output directory and the Simulation of the one shown last.
class FrameSource {
public:
    // `pvd`: the run's frame collection; frames are listed again from it on every list().
    FrameSource(std::string dir, std::string pvd, Scene scene, Options options);
    std::vector<PvdEntry> list() const;
    struct Rendered {
        Image image;
        std::size_t index = 0;
        double time = 0;
        std::size_t particles = 0;
    };
    // Frame `index` of list() (clamped to the last) seen by `camera`; throws clsph::Error when the
    // directory lists no frame or the frame cannot be read.
    Rendered render(std::size_t index, const CameraView& camera, const ImageStyle& style);
    const Scene& scene() const { return scene_; }
    const std::string& dir() const { return dir_; }
    std::vector<std::string> devices() const;

private:
    std::string dir_, pvd_;
    Scene scene_;
    Options options_;
    mutable std::mutex mutex_;  // one image at a time
    std::unique_ptr<Simulation> sim_;
    std::string loaded_;        // the file sim_ holds
    std::size_t loaded_particles_ = 0;
};

class ViewServer {
public:
    // Binds `address` (throws clsph::Error, naming it, when it cannot) and starts serving.
    ViewServer(const ServeAddress& address, FrameSource& source, const CameraView& home, double scene_size);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;
    std::string url() const { return url_of(address_); }

private:
    void routes();

    FrameSource& source_;
    CameraView home_;
    Orbit home_orbit_;
    double scene_size_;
    ServeAddress address_;
    std::unique_ptr<httplib::Server> server_;
    std::thread listener_;
};

}  // namespace clsph::app::serve
