// What the live view's two servers share (clsph run --serve: live_server.hpp; clsph view:
// view_server.hpp): the server's limits and timeouts, the page's files, JSON answers and errors,
// the camera description the page starts from, and the JPEG answer of an image.
#pragma once
#include "orbit.hpp"

#include <clsph/render.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace clsph::app::serve {

struct ServeAddress {
    std::string host = "127.0.0.1";
    int port = 8080;
};

// Threads, timeouts (a slow-loris client dropped after 5 s), the body limit, SO_REUSEADDR without
// SO_REUSEPORT (a second server on the port is refused), and the 404 / exception handlers.
void configure(httplib::Server& server);
// Binds `address` or throws clsph::Error naming it (`what`: the option, e.g. "--serve").
void bind(httplib::Server& server, const ServeAddress& address, const std::string& what, const std::string& port_hint);
std::string url_of(const ServeAddress& address);

// GET / and the page's other files.
void page_routes(httplib::Server& server);
// The page's starting camera, the limits it must keep to, and the colour map for its legend.
nlohmann::json camera_json(const Orbit& home_orbit, const CameraView& home, double scene_size);

void reply_json(httplib::Response& res, const nlohmann::json& j);
void reply_error(httplib::Response& res, int status, const std::string& message);
// The image as a JPEG; coloured by a field, X-Colour-Range: "lo hi" (the colour map's ends).
void reply_image(httplib::Response& res, const Image& image);

// --serve-host: whether an address is loopback only (127.0.0.0/8, ::1, localhost).
bool is_loopback(const std::string& host);

}  // namespace clsph::app::serve
