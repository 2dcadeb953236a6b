#include "live_server.hpp"

#include "http_common.hpp"

#include <clsph/error.hpp>

#include <httplib.h>

#include <sys/socket.h>

#include <cmath>
#include <map>
#include <string>

namespace clsph::app::serve {

namespace {

// An image of a large state on a CPU device can take seconds (the first one also builds kernels).
constexpr auto frame_wait = std::chrono::milliseconds(10000);

}  // namespace

LiveServer::LiveServer(const ServeAddress& address, LiveView& view, const CameraView& home, double scene_size)
    : view_(view),
      home_(home),
      home_orbit_(home_orbit(home)),
      scene_size_(scene_size),
      address_(address),
      server_(std::make_unique<httplib::Server>()) {
    configure(*server_);
    routes();
    bind(*server_, address, "--serve", "--serve PORT");
    port_ = address.port;
    listener_ = std::thread([this] { server_->listen_after_bind(); });
}

LiveServer::~LiveServer() {
    server_->stop();
    if (listener_.joinable()) listener_.join();
}

std::string LiveServer::url() const { return url_of(address_); }

void LiveServer::routes() {
    auto& s = *server_;
    page_routes(s);
    s.Get("/api/status", [this](const httplib::Request&, httplib::Response& res) { reply_json(res, view_.status()); });
    s.Get("/api/camera", [this](const httplib::Request&, httplib::Response& res) {
        reply_json(res, camera_json(home_orbit_, home_, scene_size_));
    });
    s.Get("/api/probes", [this](const httplib::Request& req, httplib::Response& res) {
        double after = -INFINITY;
        if (req.has_param("after")) {
            const std::string text = req.get_param_value("after");
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || end != text.c_str() + text.size() || std::isnan(v))
                return reply_error(res, 400, "after: expected a simulated time in s, got '" + text.substr(0, 40) + "'");
            after = v;
        }
        reply_json(res, view_.probes_after(after));
    });
    s.Get("/frame.jpg", [this](const httplib::Request& req, httplib::Response& res) {
        const auto parsed = parse_orbit(req.params, home_orbit_, scene_size_);
        if (!parsed.orbit) return reply_error(res, 400, parsed.error);
        std::string why;
        const auto image = view_.frame(camera_of(*parsed.orbit, home_), parsed.orbit->style, frame_wait, why);
        if (!image) return reply_error(res, 503, why);
        reply_image(res, *image);
    });
    // The page's buttons: POST only, with no body, so that a link or a prefetch changes nothing.
    auto action = [this](const char* path, void (LiveView::*what)()) {
        server_->Post(path, [this, what](const httplib::Request& req, httplib::Response& res) {
            if (!req.body.empty()) return reply_error(res, 400, "this request takes no body");
            (view_.*what)();
            reply_json(res, view_.status());
        });
        server_->Get(path, [](const httplib::Request&, httplib::Response& res) {
            res.set_header("Allow", "POST");
            reply_error(res, 405, "use POST");
        });
    };
    action("/api/pause", &LiveView::pause);
    action("/api/resume", &LiveView::resume);
    action("/api/step", &LiveView::step_once);
    action("/api/write", &LiveView::write_now);
}

}  // namespace clsph::app::serve
