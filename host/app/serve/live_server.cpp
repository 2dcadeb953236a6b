#include "live_server.hpp"

#include "jpeg.hpp"

#include <clsph/error.hpp>

#include <httplib.h>

#include <sys/socket.h>

#include <cmath>
#include <map>
#include <string>

namespace clsph::app::serve {

const std::map<std::string, std::string>& page_files();  // generated from page/ (CMake)

namespace {

// Small enough that a burst of browsers never takes more than a few threads from the run's
// machine; each image request holds one while the run thread renders.
constexpr std::size_t server_threads = 6;
constexpr std::size_t max_body_bytes = 1024;  // the page's requests carry no body
// An image of a large state on a CPU device can take seconds (the first one also builds kernels).
constexpr auto frame_wait = std::chrono::milliseconds(10000);

const char* content_type(const std::string& name) {
    auto ends = [&](const char* ext) {
        const std::string e(ext);
        return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    if (ends(".js")) return "text/javascript; charset=utf-8";
    return "application/octet-stream";
}

void reply_json(httplib::Response& res, const nlohmann::json& j) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(j.dump(), "application/json");
}

void reply_error(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_header("Cache-Control", "no-store");
    res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

}  // namespace

bool is_loopback(const std::string& host) {
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

LiveServer::LiveServer(const ServeAddress& address, LiveView& view, const CameraView& home, double scene_size)
    : view_(view),
      home_(home),
      home_orbit_(home_orbit(home)),
      scene_size_(scene_size),
      address_(address),
      server_(std::make_unique<httplib::Server>()) {
    if (address.port < 1 || address.port > 65535)
        throw Error("--serve: the port must be from 1 to 65535, got " + std::to_string(address.port));
    server_->new_task_queue = [] { return new httplib::ThreadPool(server_threads); };
    server_->set_read_timeout(5, 0);  // a client that stops sending (slow loris) is dropped
    server_->set_write_timeout(5, 0);  // a client that stops reading, too
    server_->set_keep_alive_timeout(5);
    server_->set_keep_alive_max_count(100);
    server_->set_payload_max_length(max_body_bytes);
    // SO_REUSEADDR (a restart finds the port free at once) but not httplib's default SO_REUSEPORT,
    // with which a second run on the same port would share it instead of being refused.
    server_->set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    routes();
    if (!server_->bind_to_port(address.host, address.port))
        throw Error("--serve: cannot listen on " + address.host + ":" + std::to_string(address.port) +
                    " (the port is in use, or the address is not this machine's); choose another with --serve PORT" +
                    (is_loopback(address.host) ? "" : " or --serve-host ADDR"));
    port_ = address.port;
    listener_ = std::thread([this] { server_->listen_after_bind(); });
}

LiveServer::~LiveServer() {
    server_->stop();
    if (listener_.joinable()) listener_.join();
}

std::string LiveServer::url() const {
    const std::string host = address_.host.find(':') != std::string::npos ? "[" + address_.host + "]" : address_.host;
    return "http://" + host + ":" + std::to_string(port_) + "/";
}

void LiveServer::routes() {
    auto& s = *server_;
    s.Get("/", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(page_files().at("index.html"), content_type("index.html"));
    });
    // The page's other files, by name; anything else is not found.
    s.Get(R"(/([a-z_]+\.(css|js)))", [](const httplib::Request& req, httplib::Response& res) {
        const auto& files = page_files();
        const auto it = files.find(req.matches[1].str());
        if (it == files.end()) return reply_error(res, 404, "not found: " + req.path);
        res.set_content(it->second, content_type(it->first));
    });
    s.Get("/api/status", [this](const httplib::Request&, httplib::Response& res) { reply_json(res, view_.status()); });
    s.Get("/api/camera", [this](const httplib::Request&, httplib::Response& res) {
        reply_json(res, {{"az", home_orbit_.azimuth_deg},
                         {"el", home_orbit_.elevation_deg},
                         {"dist", home_orbit_.distance},
                         {"w", home_orbit_.width},
                         {"h", home_orbit_.height},
                         {"fov", home_.fov_deg},
                         {"max_w", max_width},
                         {"max_h", max_height},
                         {"max_el", max_elevation_deg},
                         {"scene_size", scene_size_}});
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
        res.set_header("Cache-Control", "no-store");
        res.set_content(encode_jpeg(*image), "image/jpeg");  // here, on this server thread
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
    s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;  // a handler's own message
        if (res.status == 404) return reply_error(res, 404, "not found: " + req.path.substr(0, 200));
        reply_error(res, res.status, "bad request");
    });
    s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "internal error";
        try {
            std::rethrow_exception(ep);
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        reply_error(res, 500, what);
    });
}

}  // namespace clsph::app::serve
