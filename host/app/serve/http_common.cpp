#include "http_common.hpp"

#include "jpeg.hpp"

#include <clsph/error.hpp>

#include <httplib.h>

#include <sys/socket.h>

#include <cmath>
#include <cstdio>
#include <map>

namespace clsph::app::serve {

const std::map<std::string, std::string>& page_files();  // generated from page/ (CMake)

namespace {

// Small enough that a burst of browsers never takes more than a few threads from the machine;
// each image request holds one while the image is rendered.
constexpr std::size_t server_threads = 6;
constexpr std::size_t max_body_bytes = 1024;  // the page's requests carry no body

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

}  // namespace

bool is_loopback(const std::string& host) {
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

void configure(httplib::Server& s) {
    s.new_task_queue = [] { return new httplib::ThreadPool(server_threads); };
    s.set_read_timeout(5, 0);   // a client that stops sending (slow loris) is dropped
    s.set_write_timeout(5, 0);  // a client that stops reading, too
    s.set_keep_alive_timeout(5);
    s.set_keep_alive_max_count(100);
    s.set_payload_max_length(max_body_bytes);
    // SO_REUSEADDR (a restart finds the port free at once) but not httplib's default SO_REUSEPORT,
    // with which a second server on the same port would share it instead of being refused.
    s.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
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

void bind(httplib::Server& s, const ServeAddress& address, const std::string& what, const std::string& port_hint) {
    if (address.port < 1 || address.port > 65535)
        throw Error(what + ": the port must be from 1 to 65535, got " + std::to_string(address.port));
    if (!s.bind_to_port(address.host, address.port))
        throw Error(what + ": cannot listen on " + address.host + ":" + std::to_string(address.port) +
                    " (the port is in use, or the address is not this machine's); choose another with " + port_hint +
                    (is_loopback(address.host) ? "" : " or --serve-host ADDR"));
}

std::string url_of(const ServeAddress& address) {
    const std::string host = address.host.find(':') != std::string::npos ? "[" + address.host + "]" : address.host;
    return "http://" + host + ":" + std::to_string(address.port) + "/";
}

void page_routes(httplib::Server& s) {
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
}

nlohmann::json camera_json(const Orbit& o, const CameraView& home, double scene_size) {
    nlohmann::json map = nlohmann::json::array();  // the colour map at 11 points, for the legend
    for (int k = 0; k <= 10; ++k) {
        const auto c = field_colour(k / 10.0);
        map.push_back({c[0], c[1], c[2]});
    }
    return {{"az", o.azimuth_deg}, {"el", o.elevation_deg}, {"dist", o.distance},  {"w", o.width},
            {"h", o.height},       {"fov", home.fov_deg},  {"max_w", max_width},  {"max_h", max_height},
            {"max_el", max_elevation_deg}, {"scene_size", scene_size}, {"colour_map", map}};
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

void reply_image(httplib::Response& res, const Image& image) {
    res.set_header("Cache-Control", "no-store");
    if (std::isfinite(image.range[0]) && std::isfinite(image.range[1])) {
        char text[64];
        std::snprintf(text, sizeof text, "%.6g %.6g", image.range[0], image.range[1]);
        res.set_header("X-Colour-Range", text);
    }
    res.set_content(encode_jpeg(image), "image/jpeg");  // here, on this server thread
}

}  // namespace clsph::app::serve
