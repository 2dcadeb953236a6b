// clsph view DIR end to end: the tool runs the tiny dam break to a directory (compressed frames,
// one piece per device: .pvtu), then serves it; an HTTP client checks the page, the frame list, the
// first and last frames as JPEG of the size asked for (and that they differ: the water has moved),
// colour by speed (with its range), the refusals of bad input, and that a missing or empty
// directory and a port in use are clear errors (exit 1) before anything is served.
#include "support.hpp"

#include <doctest/doctest.h>
#include <httplib.h>
#include <turbojpeg.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <thread>

using namespace cli_test;

namespace {

using namespace std::chrono_literals;

int free_port() {
    const int s = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    bind(s, reinterpret_cast<sockaddr*>(&a), sizeof(a));
    socklen_t len = sizeof(a);
    getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
    close(s);
    return ntohs(a.sin_port);
}

struct Jpeg {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
};

Jpeg decode(const std::string& bytes) {
    Jpeg j;
    tjhandle h = tjInitDecompress();
    int sub = 0, space = 0;
    auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    if (tjDecompressHeader3(h, data, bytes.size(), &j.width, &j.height, &sub, &space) == 0) {
        j.rgb.resize(std::size_t{3} * static_cast<std::size_t>(j.width) * static_cast<std::size_t>(j.height));
        if (tjDecompress2(h, data, bytes.size(), j.rgb.data(), j.width, 0, j.height, TJPF_RGB, 0) != 0) j.rgb.clear();
    }
    tjDestroy(h);
    return j;
}

std::size_t pixels_differing(const Jpeg& a, const Jpeg& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 < a.rgb.size() && i + 2 < b.rgb.size(); i += 3) {
        int d = 0;
        for (std::size_t c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.rgb[i + c]) - int(b.rgb[i + c])));
        n += d > 24;
    }
    return n;
}

Jpeg get_jpeg(httplib::Client& c, const std::string& path, httplib::Headers* headers = nullptr) {
    const auto r = c.Get(path.c_str());
    REQUIRE(r);
    CAPTURE(path);
    CAPTURE(r->body.substr(0, 300));
    REQUIRE(r->status == 200);
    CHECK(r->get_header_value("Content-Type") == "image/jpeg");
    if (headers) *headers = r->headers;
    return decode(r->body);
}

}  // namespace

TEST_CASE("clsph view: a finished run's frames served, frame 0 and the last differ; bad input refused") {
    const std::string out = work_dir("view_run");
    std::string log;
    // Compressed frames in one piece per device (.pvtu): the readers clsph resume uses.
    REQUIRE(run(args({{"run", scene}, tiny, {"--steps", "150", "--every", "0.01", "--out", out, "--no-checkpoint", "--devices",
                                             "platform:pocl", "--compress", "--pieces"}}),
                log) == 0);
    const int port = free_port();
    const std::string view_log = std::string(CLSPH_CLI_WORK) + "/view.log";
    // Rendered on one CPU device: any OpenCL device will do.
    Process p(CLSPH_CLI, {"view", out, "--port", std::to_string(port), "--devices", "0"}, view_log);
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port);
    c->set_read_timeout(60, 0);
    c->set_connection_timeout(2, 0);
    bool up = false;
    for (int i = 0; i < 500 && !up; ++i) {
        const auto r = c->Get("/api/status");
        up = r && r->status == 200;
        if (!up) std::this_thread::sleep_for(20ms);
    }
    REQUIRE(up);
    CHECK(read_text(view_log).find("clsph: viewing " + out + " at http://127.0.0.1:" + std::to_string(port) + "/") !=
          std::string::npos);

    {  // a port in use: exit 1 with the reason
        CHECK(run({"view", out, "--port", std::to_string(port)}, log) == 1);
        CHECK(log.find("cannot listen on 127.0.0.1:" + std::to_string(port)) != std::string::npos);
    }

    const auto page = c->Get("/");
    REQUIRE(page);
    CHECK(page->status == 200);
    CHECK(page->body.find("id=\"timeline\"") != std::string::npos);
    const auto status = nlohmann::json::parse(c->Get("/api/status")->body);
    CHECK(status.at("mode") == "view");
    const std::size_t frames = status.at("frames").get<std::size_t>();
    CHECK(frames >= 3);
    CHECK(status.at("times").size() == frames);

    const Jpeg first = get_jpeg(*c, "/frame.jpg?frame=0&w=320&h=192");
    CHECK(first.width == 320);
    CHECK(first.height == 192);
    httplib::Headers h;
    const std::string last_path = "/frame.jpg?frame=" + std::to_string(frames - 1) + "&w=320&h=192";
    const Jpeg last = get_jpeg(*c, last_path, &h);
    CHECK(last.width == 320);
    CHECK(last.height == 192);
    const auto xf = h.find("X-Frame");
    REQUIRE(xf != h.end());
    CHECK(xf->second.rfind(std::to_string(frames - 1) + " ", 0) == 0);
    // The column of water has collapsed: a good part of the picture changed.
    CHECK(pixels_differing(first, last) > first.rgb.size() / 3 / 100);
    // The same frame again: the same picture (one Simulation per frame shown, nothing else moves).
    CHECK(pixels_differing(last, get_jpeg(*c, last_path)) == 0);

    // Coloured by speed: at rest in frame 0 (range 0 to 0), moving in the last (a range above 0), and
    // another picture than the uniform one there.
    get_jpeg(*c, "/frame.jpg?frame=0&w=320&h=192&colour=speed", &h);
    REQUIRE(h.find("X-Colour-Range") != h.end());
    CHECK(h.find("X-Colour-Range")->second == "0 0");
    const Jpeg fast = get_jpeg(*c, last_path + "&colour=speed", &h);
    REQUIRE(h.find("X-Colour-Range") != h.end());
    const double top = std::stod(h.find("X-Colour-Range")->second.substr(2));
    CHECK(top > 0.1);
    CHECK(pixels_differing(fast, last) > last.rgb.size() / 3 / 50);
    get_jpeg(*c, last_path + "&colour=pressure&lo=0&hi=500", &h);
    CHECK(h.find("X-Colour-Range")->second == "0 500");

    // Bad input: 4xx, and the server goes on.
    for (const char* bad : {"/frame.jpg?frame=-1", "/frame.jpg?frame=x", "/frame.jpg?frame=1&frame=2", "/frame.jpg?colour=heat",
                            "/frame.jpg?colour=speed&lo=2&hi=1", "/frame.jpg?lo=nan", "/frame.jpg?w=99999"}) {
        CAPTURE(bad);
        const auto r = c->Get(bad);
        REQUIRE(r);
        CHECK(r->status == 400);
    }
    for (const char* missing : {"/frame.jpg?frame=100000", "/nothing", "/api/nothing", "/api/pause"}) {
        CAPTURE(missing);
        const auto r = c->Get(missing);
        REQUIRE(r);
        CHECK(r->status == 404);
    }
    const auto post = c->Post("/api/pause");  // no run to pause here
    REQUIRE(post);
    CHECK(post->status == 404);
    CHECK(c->Get("/api/status")->status == 200);

    p.interrupt();
    CHECK(p.wait(30) == 0);
}

TEST_CASE("clsph view: a missing directory, one that is not a run's, and a run without frames are errors") {
    std::string log;
    const std::string missing = work_dir("view_missing");
    CHECK(run({"view", missing, "--port", std::to_string(free_port())}, log) == 1);
    CHECK(log.find("is not a directory") != std::string::npos);
    const std::string empty = work_dir("view_empty");
    fs::create_directories(empty);
    CHECK(run({"view", empty, "--port", std::to_string(free_port())}, log) == 1);
    CHECK(log.find("run.json") != std::string::npos);
    // run.json but no frames yet (a run that has not written its first frame).
    const std::string bare = work_dir("view_bare");
    REQUIRE(run(args({{"run", scene}, tiny, {"--steps", "2", "--every", "10", "--out", bare, "--no-checkpoint", "--devices", "0"}}),
                log) == 0);
    for (const auto& e : fs::directory_iterator(bare))
        if (e.path().extension() == ".pvd") fs::remove(e.path());
    CHECK(run({"view", bare, "--port", std::to_string(free_port())}, log) == 1);
    CHECK(log.find("no frame collection") != std::string::npos);
}
