// clsph run --serve end to end: the tool runs the tiny dam break with the live view on, and an
// HTTP client (cpp-httplib's, and a plain socket for what a client library would not send) checks
// what a browser gets: the page, JPEG frames of the size asked for, a camera that moves the image,
// pause / step / resume, the refusals of bad input, 20 clients at once, a port in use, Ctrl-C with
// the server; and that the run's frames and stats are byte for byte those of a run without it.
#include "support.hpp"

#include <doctest/doctest.h>
#include <httplib.h>
#include <turbojpeg.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <memory>
#include <thread>

using namespace cli_test;

namespace {

using namespace std::chrono_literals;

// A port nobody listens on now (the kernel's choice for port 0).
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

// A connected plain socket to the server, or -1.
int connect_to(int port) {
    const int s = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    if (connect(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
        close(s);
        return -1;
    }
    return s;
}

// What the server answers to `raw` on a socket of its own: the status line, or "" when it closed.
std::string raw_exchange(int port, const std::string& raw) {
    const int s = connect_to(port);
    if (s < 0) return "no connection";
    send(s, raw.data(), raw.size(), 0);
    timeval tv{8, 0};
    setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    char buf[256] = {};
    const auto n = recv(s, buf, sizeof(buf) - 1, 0);
    close(s);
    if (n <= 0) return "";
    const std::string got(buf, static_cast<std::size_t>(n));
    return got.substr(0, got.find("\r\n"));
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

nlohmann::json get_json(httplib::Client& c, const std::string& path) {
    const auto r = c.Get(path.c_str());
    REQUIRE(r);
    REQUIRE(r->status == 200);
    return nlohmann::json::parse(r->body);
}

std::uint64_t step_now(httplib::Client& c) { return get_json(c, "/api/status").at("step").get<std::uint64_t>(); }

std::unique_ptr<httplib::Client> client(int port) {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port);
    c->set_read_timeout(15, 0);
    c->set_connection_timeout(2, 0);
    return c;
}

// Waits until the run's status says `state` (the server answers from before the kernels build).
bool wait_for_state(httplib::Client& c, const std::string& state, std::chrono::seconds limit = 90s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
        if (const auto r = c.Get("/api/status"); r && r->status == 200 && nlohmann::json::parse(r->body).at("state") == state)
            return true;
        std::this_thread::sleep_for(20ms);
    }
    return false;
}

std::vector<std::string> tiny_run(const std::string& out) {
    // 120 steps: long enough to pause inside, short enough to run twice here. The cuts fixed
    // (--balance off): the dynamic balance follows measured times, which a pause and the images
    // change, and with the cuts the order of the per-device sums in stats.csv (kinetic energy).
    return args({{"run", scene}, tiny, {"--steps", "120", "--every", "0.002", "--out", out, "--no-checkpoint", "--devices",
                                        "platform:pocl", "--balance", "off"}});
}

}  // namespace

TEST_CASE("--serve: the page, frames, camera, pause, step, bad input, 20 clients; the run's files unchanged") {
    const std::string plain = work_dir("serve_plain"), served = work_dir("serve_served");
    std::string log;
    REQUIRE(run(tiny_run(plain), log) == 0);

    const int port = free_port();
    const std::string served_log = std::string(CLSPH_CLI_WORK) + "/serve_served.log";
    Process p(CLSPH_CLI, args({tiny_run(served), {"--serve", std::to_string(port)}}), served_log);
    auto c = client(port);
    // Paused as soon as it answers: every check below happens inside the run.
    bool up = false;
    for (int i = 0; i < 400 && !up; ++i) {
        const auto r = c->Post("/api/pause");
        up = r && r->status == 200;
        if (!up) std::this_thread::sleep_for(20ms);
    }
    REQUIRE(up);
    CHECK(read_text(served_log).find("clsph: live view at http://127.0.0.1:" + std::to_string(port) + "/") != std::string::npos);

    {  // a port in use is refused before the run starts, with no output directory
        const std::string other = work_dir("serve_port_taken");
        CHECK(run(args({tiny_run(other), {"--serve", std::to_string(port)}}), log) == 1);
        CHECK(log.find("cannot listen on 127.0.0.1:" + std::to_string(port)) != std::string::npos);
        CHECK(!fs::exists(other));
    }

    REQUIRE(wait_for_state(*c, "paused"));
    // The page and its files; nothing else.
    const auto page = c->Get("/");
    REQUIRE(page);
    CHECK(page->status == 200);
    CHECK(page->body.find("clsph live view") != std::string::npos);
    for (const char* f : {"/page.js", "/page.css"}) {
        const auto r = c->Get(f);
        REQUIRE(r);
        CHECK(r->status == 200);
    }
    for (const char* f : {"/nothing", "/page.jsx", "/../CMakeLists.txt", "/api/nothing", "/frame.png"}) {
        CAPTURE(f);
        const auto r = c->Get(f);
        REQUIRE(r);
        CHECK(r->status == 404);
    }

    // A frame: a JPEG of the size asked for; another camera, another image.
    const auto home = get_json(*c, "/api/camera");
    // The first image builds the surface and render kernels: it may take a few tries (503 says "try again").
    auto a = c->Get("/frame.jpg?w=320&h=200");
    for (int i = 0; i < 30 && a && a->status == 503; ++i) {
        MESSAGE(a->body);
        a = c->Get("/frame.jpg?w=320&h=200");
    }
    REQUIRE(a);
    REQUIRE(a->status == 200);
    CHECK(a->get_header_value("Content-Type") == "image/jpeg");
    const Jpeg ja = decode(a->body);
    CHECK(ja.width == 320);
    CHECK(ja.height == 200);
    const std::string turned = "/frame.jpg?w=320&h=200&az=" + std::to_string(home.at("az").get<double>() + 90.0) + "&el=60";
    const auto b = c->Get(turned.c_str());
    REQUIRE(b);
    REQUIRE(b->status == 200);
    const Jpeg jb = decode(b->body);
    REQUIRE(jb.rgb.size() == ja.rgb.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ja.rgb.size(); ++i) differ += std::abs(int(ja.rgb[i]) - int(jb.rgb[i])) > 24;
    CHECK(differ > ja.rgb.size() / 100);
    // Coloured by device (two devices, each owning a slab with --balance off): another image again.
    const auto by_device = c->Get("/frame.jpg?w=320&h=200&colour=device");
    REQUIRE(by_device);
    REQUIRE(by_device->status == 200);
    const Jpeg jd = decode(by_device->body);
    REQUIRE(jd.rgb.size() == ja.rgb.size());
    std::size_t recoloured = 0;
    for (std::size_t i = 0; i < ja.rgb.size(); ++i) recoloured += std::abs(int(ja.rgb[i]) - int(jd.rgb[i])) > 24;
    CHECK(recoloured > 0);

    // Bad cameras and requests: 4xx, and the run is as it was.
    const std::uint64_t paused_at = step_now(*c);
    for (const char* bad : {"/frame.jpg?az=nan", "/frame.jpg?az=inf", "/frame.jpg?el=95", "/frame.jpg?dist=-1",
                            "/frame.jpg?dist=1e300", "/frame.jpg?w=100000", "/frame.jpg?w=12.5", "/frame.jpg?h=0",
                            "/frame.jpg?az=1x", "/frame.jpg?zoom=2", "/frame.jpg?colour=red", "/frame.jpg?az=1&az=2", "/api/probes?after=abc"}) {
        CAPTURE(bad);
        const auto r = c->Get(bad);
        REQUIRE(r);
        CHECK(r->status == 400);
        CHECK(r->body.find("error") != std::string::npos);
    }
    {
        const auto r = c->Get("/api/pause");
        REQUIRE(r);
        CHECK(r->status == 405);
        const auto big = c->Post("/api/resume", std::string(64 * 1024, 'x'), "text/plain");
        REQUIRE(big);
        CHECK(big->status == 413);
        const auto small = c->Post("/api/resume", "x", "text/plain");
        REQUIRE(small);
        CHECK(small->status == 400);
    }
    CHECK(raw_exchange(port, "GARBAGE\r\n\r\n").find(" 400 ") != std::string::npos);
    CHECK(raw_exchange(port, "GET /" + std::string(20000, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n").find(" 414 ") != std::string::npos);

    // A slow client (the start of a request, then nothing) is dropped after the read timeout,
    // while another is served meanwhile.
    std::atomic<bool> slow_dropped{false};
    std::thread slow([&] {
        const auto t0 = std::chrono::steady_clock::now();
        const std::string got = raw_exchange(port, "GET /api/status HTTP/1.1\r\nHost: x\r\n");
        slow_dropped = (got.empty() || got.find(" 408 ") != std::string::npos || got.find(" 400 ") != std::string::npos) &&
                       std::chrono::steady_clock::now() - t0 < 8s;
    });

    // 20 clients at once, each asking for frames (one view: a CPU device takes about a second an
    // image here) and the status: none is refused outright (a 503 says "try again"), and the run's
    // step counter stays where the pause left it.
    std::atomic<int> ok{0}, busy{0}, failed{0};
    std::vector<std::thread> clients;
    for (int k = 0; k < 20; ++k)
        clients.emplace_back([&] {
            auto mine = client(port);
            for (int i = 0; i < 3; ++i) {
                const std::string path = "/frame.jpg?w=160&h=100&az=" + std::to_string(10 * i);
                const auto r = mine->Get(path.c_str());
                if (r && r->status == 200 && decode(r->body).width == 160)
                    ++ok;
                else if (r && r->status == 503)
                    ++busy;
                else
                    ++failed;
                if (!mine->Get("/api/status")) ++failed;
            }
        });
    for (auto& t : clients) t.join();
    CHECK(failed == 0);
    CHECK(ok >= 20);
    slow.join();
    CHECK(slow_dropped);

    // Paused: the step counter stands; one step moves it by one; resumed, it moves on.
    CHECK(step_now(*c) == paused_at);
    std::this_thread::sleep_for(300ms);
    CHECK(step_now(*c) == paused_at);
    REQUIRE(c->Post("/api/step"));
    std::uint64_t after_step = paused_at;
    for (int i = 0; i < 200 && after_step == paused_at; ++i) {
        std::this_thread::sleep_for(10ms);
        after_step = step_now(*c);
    }
    CHECK(after_step == paused_at + 1);
    std::this_thread::sleep_for(200ms);
    CHECK(step_now(*c) == paused_at + 1);
    REQUIRE(c->Post("/api/resume"));
    CHECK(p.wait(120) == 0);

    // The live view took nothing from the run: frames and stats byte for byte those without it.
    CHECK(read_text(served + "/stats.csv") == read_text(plain + "/stats.csv"));
    const auto frames = clsph::read_pvd(plain + "/dam_break.pvd");
    REQUIRE(frames.size() >= 3);
    REQUIRE(clsph::read_pvd(served + "/dam_break.pvd").size() == frames.size());
    for (const auto& f : frames) {
        CAPTURE(f.file);
        CHECK(read_text(served + "/" + f.file) == read_text(plain + "/" + f.file));
    }
    // And the server went with the run.
    CHECK(connect_to(port) < 0);
}

TEST_CASE("--serve: write now gives a frame and a checkpoint; Ctrl-C stops the run and the server") {
    const std::string out = work_dir("serve_write");
    const int port = free_port();
    const std::string out_log = std::string(CLSPH_CLI_WORK) + "/serve_write.log";
    Process p(CLSPH_CLI, args({{"run", scene}, tiny, {"--until", "100", "--every", "50", "--out", out, "--devices", "platform:pocl", "--serve", std::to_string(port)}}),
              out_log);
    auto c = client(port);
    REQUIRE(wait_for_state(*c, "running"));
    const auto r = c->Post("/api/write");
    REQUIRE(r);
    CHECK(r->status == 200);
    std::string written;
    for (int i = 0; i < 300 && written.empty(); ++i) {
        std::this_thread::sleep_for(20ms);
        written = get_json(*c, "/api/status").at("written").get<std::string>();
    }
    CHECK(written.find("frame 1 at t = ") != std::string::npos);
    CHECK(written.find("checkpoint_") != std::string::npos);
    CHECK(count_files(out, "checkpoint_", ".clsph") == 1);
    p.interrupt();
    CHECK(p.wait(60) == 130);
    CHECK(connect_to(port) < 0);
    CHECK(clsph::read_pvd(out + "/dam_break.pvd").size() >= 3);  // t = 0, the one asked for, the last
}

TEST_CASE("--serve on the command line: a port out of range, --serve-host without --serve") {
    std::string log;
    const std::string out = work_dir("serve_args");
    CHECK(run(args({{"run", scene}, tiny, {"--serve", "70000", "--out", out}}), log) == 1);
    CHECK(log.find("--serve: expected a port number from 1 to 65535, got '70000'") != std::string::npos);
    CHECK(run(args({{"run", scene}, tiny, {"--serve-host", "0.0.0.0", "--out", out}}), log) == 1);
    CHECK(log.find("--serve-host") != std::string::npos);
    CHECK(!fs::exists(out));
}
