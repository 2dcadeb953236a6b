#include "view_server.hpp"

#include <clsph/error.hpp>

#include <httplib.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>

namespace clsph::app::serve {

FrameSource::FrameSource(std::string dir, std::string pvd, Scene scene, Options options)
    : dir_(std::move(dir)), pvd_(std::move(pvd)), scene_(std::move(scene)), options_(std::move(options)) {}

std::vector<PvdEntry> FrameSource::list() const {
    // A running run rewrites its .pvd as frames come (PvdWriter: whole files, by rename).
    try {
        return read_pvd(pvd_);
    } catch (const Error&) {
        return {};
    }
}

std::vector<std::string> FrameSource::devices() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return sim_ ? sim_->device_names() : std::vector<std::string>{};
}

FrameSource::Rendered FrameSource::render(std::size_t index, const CameraView& camera, const ImageStyle& style) {
    const auto frames = list();
    if (frames.empty()) throw Error(pvd_ + " lists no frame (yet)");
    index = std::min(index, frames.size() - 1);
    const std::string file = dir_ + "/" + frames[index].file;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!sim_ || loaded_ != file) {
        FrameFields present;
        const Particles p = read_vtu(file, &present);  // a frame without velocities draws them at rest
        sim_.reset();  // the old one's device memory first
        sim_ = std::make_unique<Simulation>(scene_, p, options_);
        loaded_ = file;
        loaded_particles_ = p.size();
    }
    Rendered r;
    r.image = sim_->image(camera, style);
    r.index = index;
    r.time = frames[index].time;
    r.particles = loaded_particles_;
    return r;
}

namespace {

std::optional<std::size_t> whole_number(const std::string& text) {
    if (text.empty() || text.size() > 12) return std::nullopt;
    for (char c : text)
        if (c < '0' || c > '9') return std::nullopt;
    return static_cast<std::size_t>(std::strtoull(text.c_str(), nullptr, 10));
}

}  // namespace

ViewServer::ViewServer(const ServeAddress& address, FrameSource& source, const CameraView& home, double scene_size)
    : source_(source),
      home_(home),
      home_orbit_(home_orbit(home)),
      scene_size_(scene_size),
      address_(address),
      server_(std::make_unique<httplib::Server>()) {
    configure(*server_);
    routes();
    bind(*server_, address, "clsph view", "--port PORT");
    listener_ = std::thread([this] { server_->listen_after_bind(); });
}

ViewServer::~ViewServer() {
    server_->stop();
    if (listener_.joinable()) listener_.join();
}

void ViewServer::routes() {
    auto& s = *server_;
    page_routes(s);
    s.Get("/api/camera", [this](const httplib::Request&, httplib::Response& res) {
        reply_json(res, camera_json(home_orbit_, home_, scene_size_));
    });
    s.Get("/api/status", [this](const httplib::Request&, httplib::Response& res) {
        const auto frames = source_.list();
        nlohmann::json times = nlohmann::json::array();
        for (const auto& f : frames) times.push_back(f.time);
        reply_json(res, {{"mode", "view"},
                         {"state", "viewing"},
                         {"dir", source_.dir()},
                         {"frames", frames.size()},
                         {"times", times},
                         {"devices", source_.devices()}});
    });
    s.Get("/api/probes", [](const httplib::Request&, httplib::Response& res) {
        reply_json(res, {{"names", nlohmann::json::array()}, {"rows", nlohmann::json::array()}});
    });
    s.Get("/frame.jpg", [this](const httplib::Request& req, httplib::Response& res) {
        // frame=N: the N-th frame the .pvd lists (left out: the last); the rest is the camera.
        std::multimap<std::string, std::string> camera;
        std::size_t index = static_cast<std::size_t>(-1);
        for (const auto& [key, value] : req.params) {
            if (key != "frame") {
                camera.emplace(key, value);
                continue;
            }
            const auto n = whole_number(value);
            if (!n || req.params.count("frame") > 1)
                return reply_error(res, 400, "frame must be given once, as a frame number from 0, got '" + value.substr(0, 40) + "'");
            index = *n;
        }
        const auto parsed = parse_orbit(camera, home_orbit_, scene_size_);
        if (!parsed.orbit) return reply_error(res, 400, parsed.error);
        const std::size_t count = source_.list().size();
        if (count == 0) return reply_error(res, 503, "the directory lists no frame yet");
        if (index != static_cast<std::size_t>(-1) && index >= count)
            return reply_error(res, 404, "no frame " + std::to_string(index) + " (" + std::to_string(count) + " frames: 0 to " +
                                             std::to_string(count - 1) + ")");
        FrameSource::Rendered r;
        try {
            r = source_.render(index, camera_of(*parsed.orbit, home_), parsed.orbit->style);
        } catch (const Error& e) {
            return reply_error(res, 503, e.what());
        }
        res.set_header("X-Frame", std::to_string(r.index) + " " + std::to_string(r.time));
        reply_image(res, r.image);
    });
}

}  // namespace clsph::app::serve
