// The live view's HTTP server (clsph run --serve): the page, the images and the run's status on a
// few threads of its own (cpp-httplib), bound before the run starts so that a port in use is an
// error before anything is written. Stopped, and its threads joined, when it goes.
#pragma once
#include "http_common.hpp"
#include "live_view.hpp"
#include "orbit.hpp"

#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace clsph::app::serve {

class LiveServer {
public:
    // Binds `address` (throws clsph::Error, naming it, when it cannot: a port in use, a host that
    // is not this machine's) and starts serving `view`; `home`: the scene's camera, `scene_size`:
    // the domain's diagonal (m), for the limits on the camera's distance.
    LiveServer(const ServeAddress& address, LiveView& view, const CameraView& home, double scene_size);
    ~LiveServer();  // stops serving and joins the threads
    LiveServer(const LiveServer&) = delete;
    LiveServer& operator=(const LiveServer&) = delete;

    int port() const { return port_; }  // as bound (the one asked for)
    std::string url() const;

private:
    void routes();

    LiveView& view_;
    CameraView home_;
    Orbit home_orbit_;
    double scene_size_;
    ServeAddress address_;
    int port_ = 0;
    std::unique_ptr<httplib::Server> server_;
    std::thread listener_;
};

}  // namespace clsph::app::serve
