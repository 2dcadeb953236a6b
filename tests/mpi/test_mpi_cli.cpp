// `mpirun -np 2 clsph run` (issue 21), started as a user would start it: the frames' pieces together
// hold every particle exactly once and equal the same run in one process on the node's two devices
// bit for bit; rank 0 writes the run's files (the CSV frames gathered from every rank); a rank whose device fails stops every rank with its
// message; SIGTERM to mpirun ends the run as it does for one process. CTest runs this program alone
// (not under mpirun) with POCL_DEVICES="pthread pthread".
#include "mpi_cli_support.hpp"
#include "process.hpp"

#include <clsph/io.hpp>
#include <nlohmann/json.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace clsph;

using namespace mpi_cli_test;

TEST_CASE("mpirun -np 2 clsph run: the pieces hold every particle once, bitwise the run in one process") {
    const std::string across = work_dir("mpi_across"), one = work_dir("mpi_one");
    const std::vector<std::string> common = join({"run", scene}, join(tiny, {"--steps", "60", "--every", "100", "--csv"}));
    std::string log;
    int code = run_program(CLSPH_MPIEXEC, mpi_args(join(common, {"--out", across})), log);
    INFO(log);
    REQUIRE(code == 0);
    CHECK(log.find("rank 0: #0") != std::string::npos);
    CHECK(log.find("rank 1: #1") != std::string::npos);
    std::string log1;
    REQUIRE(run_program(CLSPH_CLI, join(common, {"--out", one, "--devices", "0,1", "--no-checkpoint"}), log1) == 0);

    // The last frame: two pieces named by the index, which read back as one frame.
    const std::string index = across + "/frame_00001.pvtu";
    REQUIRE(fs::exists(index));
    const auto sources = read_pvtu_sources(index);
    CHECK(sources == std::vector<std::string>{"frame_00001_p0.vtu", "frame_00001_p1.vtu"});
    CHECK(same_frame(index, one + "/frame_00001.vtu"));
    // Rank 0's files: the collection names the index; stats and run.json list every rank.
    const auto frames = read_pvd(across + "/dam_break.pvd");
    REQUIRE(frames.size() == 2);
    CHECK(frames.back().file == "frame_00001.pvtu");
    const auto j = read_json(across + "/run.json");
    CHECK(j.at("status") == "completed");
    const auto devices = j.at("devices").dump();
    CHECK(devices.find("rank 0: ") != std::string::npos);
    CHECK(devices.find("rank 1: ") != std::string::npos);
    CHECK(cli_test::read_text(across + "/stats.csv") == cli_test::read_text(one + "/stats.csv"));
    // --csv: rank 0 writes the whole frame, gathered in slab order: byte for byte one process's.
    for (const char* f : {"/frame_00000.csv", "/frame_00001.csv"}) {
        INFO(f);
        REQUIRE(fs::exists(across + f));
        CHECK(cli_test::read_text(across + f) == cli_test::read_text(one + f));
    }
    CHECK(!fs::exists(across + "/frame_00001_p1.csv"));
}

TEST_CASE("mpirun -np 2 clsph run with a floating box: body_box.csv and run.json's bodies byte for byte one process's") {
    // scenes/floating_box.json with shallower water, as the CLI suite's floating test; mDBC walls.
    const std::string floating = std::string(CLSPH_SOURCE_DIR) + "/scenes/floating_box.json";
    const std::vector<std::string> shallow = {"--set", "fluid[0].max=[0.8,0.125,0.1]", "--set", "boundaries.boxes[0].min=[0.32,0,0.2]",
                                              "--set", "boundaries.boxes[0].max=[0.48,0.12,0.32]"};
    const std::string across = work_dir("mpi_floating_across"), one = work_dir("mpi_floating_one");
    const std::vector<std::string> common = join({"run", floating}, join(shallow, {"--steps", "20", "--every", "100"}));
    std::string log;
    const int code = run_program(CLSPH_MPIEXEC, mpi_args(join(common, {"--out", across})), log);
    INFO(log);
    REQUIRE(code == 0);
    std::string log1;
    REQUIRE(run_program(CLSPH_CLI, join(common, {"--out", one, "--devices", "0,1", "--no-checkpoint"}), log1) == 0);
    const std::string rows = cli_test::read_text(across + "/body_box.csv");
    CHECK(std::count(rows.begin(), rows.end(), '\n') == 22);  // the header, the start and a row a step
    CHECK(rows == cli_test::read_text(one + "/body_box.csv"));
    CHECK(read_json(across + "/run.json").at("bodies") == read_json(one + "/run.json").at("bodies"));
    CHECK(cli_test::read_text(across + "/stats.csv") == cli_test::read_text(one + "/stats.csv"));
}

TEST_CASE("across ranks: a checkpoint at the end, and clsph resume across the ranks goes on bitwise") {
    const std::string across = work_dir("mpi_resume"), one = work_dir("mpi_resume_one");
    const std::vector<std::string> run = join({"run", scene}, join(tiny, {"--every", "100"}));
    std::string log;
    REQUIRE(run_program(CLSPH_MPIEXEC, mpi_args(join(run, {"--steps", "30", "--out", across})), log) == 0);
    INFO(log);
    REQUIRE(fs::exists(across + "/checkpoint_00030.clsph"));
    REQUIRE(run_program(CLSPH_MPIEXEC, mpi_args({"resume", across, "--steps", "30"}), log) == 0);
    CHECK(log.find("resuming") != std::string::npos);
    REQUIRE(fs::exists(across + "/checkpoint_00060.clsph"));
    std::string log1;
    REQUIRE(run_program(CLSPH_CLI, join(run, {"--steps", "60", "--out", one, "--devices", "0,1", "--no-checkpoint"}), log1) == 0);
    // The last frames by id, bit for bit; every step's row the same.
    const auto frames = read_pvd(across + "/dam_break.pvd"), frames1 = read_pvd(one + "/dam_break.pvd");
    REQUIRE(!frames.empty());
    REQUIRE(!frames1.empty());
    CHECK(frames.back().time == frames1.back().time);
    CHECK(same_frame(across + "/" + frames.back().file, one + "/" + frames1.back().file));
    CHECK(cli_test::read_text(across + "/stats.csv") == cli_test::read_text(one + "/stats.csv"));
    const auto j = read_json(across + "/run.json");
    CHECK(j.at("resumes").size() == 1);
}

TEST_CASE("a rank whose device fails stops every rank with that rank's message and a non-zero status") {
    const std::string out = work_dir("mpi_fault");
    const std::vector<std::string> run = join({"run", scene}, join(tiny, {"--until", "0.5", "--out", out}));
    // Two application contexts: rank 1 alone gets the fault (its 400th kernel launch fails), and
    // runs the test build of the tool (clsph-faulty: the shipped clsph ignores CLSPH_TEST_FAULT).
    std::vector<std::string> a = {CLSPH_MPIEXEC_NUMPROC_FLAG, "1"};
    for (const char* f : CLSPH_MPIEXEC_FLAGS) a.push_back(f);
    a.push_back(CLSPH_CLI);
    a.insert(a.end(), run.begin(), run.end());
    a.insert(a.end(), {":", CLSPH_MPIEXEC_NUMPROC_FLAG, "1", "env", "CLSPH_TEST_FAULT=enqueue:400", CLSPH_FAULTY_CLI});
    a.insert(a.end(), run.begin(), run.end());
    std::string log;
    const auto t0 = std::chrono::steady_clock::now();
    const int code = run_program(CLSPH_MPIEXEC, a, log, 90);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(log);
    CHECK(code != 0);
    CHECK(code != -1000);  // not a hang ended by the timeout
    CHECK(log.find("rank 1 of 2") != std::string::npos);
    CHECK(log.find("CL_") != std::string::npos);  // the injected OpenCL error, named
    MESSAGE("stopped after " << seconds << " s");
}

TEST_CASE("SIGTERM to mpirun ends every rank as one process ends: a final frame, run.json interrupted") {
    const std::string out = work_dir("mpi_sigterm");
    std::string log;
    const std::string path = std::string(CLSPH_CLI_WORK) + "/mpi_sigterm.log";
    int code = 0;
    {
        cli_test::Process p(CLSPH_MPIEXEC, mpi_args(join({"run", scene}, join(tiny, {"--until", "100", "--every", "0.01", "--out", out}))),
                            path);
        // Once the run is under way (a few frames written), as a user's Ctrl-C or a batch system would.
        for (int i = 0; i < 600 && !fs::exists(out + "/frame_00003.pvtu"); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        REQUIRE(fs::exists(out + "/frame_00003.pvtu"));
        p.signal(SIGTERM);
        code = p.wait(60);
    }
    log = cli_test::read_text(path);
    INFO(log);
    CHECK(code != -1000);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "interrupted");
    // The final frame's index names both pieces, and they exist.
    const auto frames = read_pvd(out + "/dam_break.pvd");
    REQUIRE(!frames.empty());
    for (const auto& s : read_pvtu_sources(out + "/" + frames.back().file)) CHECK(fs::exists(out + "/" + s));
}

namespace {

// The lines of `log` from the first holding `from` up to (not including) the first after it holding `to`.
std::string section(const std::string& log, const std::string& from, const std::string& to) {
    const auto a = log.find(from);
    if (a == std::string::npos) return {};
    const auto b = log.find(to, a);
    return log.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

}  // namespace

TEST_CASE("--dry-run across ranks: the plan of every rank's devices, each rank's measured peak; nothing written") {
    const std::string across = work_dir("mpi_dry"), one = work_dir("mpi_dry_one");
    const std::vector<std::string> dry = join({"run", scene}, join(tiny, {"--dry-run", "--steps", "20"}));
    std::string log, log1;
    REQUIRE(run_program(CLSPH_MPIEXEC, mpi_args(join(dry, {"--out", across})), log) == 0);
    INFO(log);
    REQUIRE(run_program(CLSPH_CLI, join(dry, {"--out", one, "--devices", "0,1"}), log1) == 0);
    INFO(log1);
    CHECK(!fs::exists(across));
    // The plan of the chain (rank 0's device, then rank 1's) is the plan one process makes of the same two.
    const std::string plan = section(log, "memory plan", "  measured:"), plan1 = section(log1, "memory plan", "  measured:");
    REQUIRE(!plan.empty());
    CHECK(section(plan, "memory plan", "  ranks:") == plan1);
    CHECK(plan.find("ranks: #0 on rank 0, #1 on rank 1") != std::string::npos);
    // Said once (by rank 0), with a measured line for each rank's device.
    CHECK(log.find("clsph run --dry-run:") == log.rfind("clsph run --dry-run:"));
    const std::string measured = section(log, "  measured:", "first time step");
    CHECK(measured.find("#0 ") != std::string::npos);
    CHECK(measured.find("#1 ") != std::string::npos);
}

TEST_CASE("across ranks a scene too large for a rank's device stops before allocating, naming physics.dp") {
    const std::string out = work_dir("mpi_too_large");
    std::vector<std::string> big = tiny;
    big[1] = "physics.dp=0.0007";  // about 24 M particles: more than 1 GiB a device
    ::setenv("POCL_MEMORY_LIMIT", "1", 1);
    std::string log;
    const int code = run_program(CLSPH_MPIEXEC, mpi_args(join({"run", scene}, join(big, {"--out", out}))), log, 300);
    ::unsetenv("POCL_MEMORY_LIMIT");
    INFO(log);
    CHECK(code != 0);
    CHECK(code != -1000);
    CHECK(log.find("physics.dp = 0.0007: the scene needs") != std::string::npos);
    CHECK(log.find("setting up the devices") == std::string::npos);
}

// The cuts held at the balancer's first (static) ones, so that both runs split alike: the mesh's
// parts are welded in slab order, so its vertex order follows the cuts.
TEST_CASE("--surface --render across ranks: rank 0 writes the mesh and the image, byte for byte one process's") {
    for (const char* method : {"surface", "splat"}) {
        CAPTURE(method);
        const std::string across = work_dir(std::string("mpi_surface_") + method), one = work_dir(std::string("mpi_surface_one_") + method);
        const std::vector<std::string> run = join({"run", scene}, join(tiny, {"--steps", "10", "--every", "100", "--surface",
                                                                               "--render", "--render-method", method,
                                                                               "--balance", "static"}));
        std::string log, log1;
        REQUIRE(run_program(CLSPH_MPIEXEC, mpi_args(join(run, {"--out", across})), log) == 0);
        INFO(log);
        REQUIRE(run_program(CLSPH_CLI, join(run, {"--out", one, "--devices", "0,1", "--no-checkpoint"}), log1) == 0);
        INFO(log1);
        for (const char* f : {"/surface_00000.vtp", "/surface_00001.vtp", "/render_00000.png", "/render_00001.png"}) {
            CAPTURE(f);
            const bool splat_mesh = std::string(method) == "splat" && std::string(f).find(".vtp") != std::string::npos;
            if (splat_mesh && !fs::exists(one + f)) continue;  // --surface with splats: as one process does
            REQUIRE(fs::exists(across + f));
            const std::string text = cli_test::read_text(across + f);
            CHECK(text.size() > 1000);  // a mesh with triangles, a picture with something in it
            if (!splat_mesh && std::string(f).find(".vtp") != std::string::npos)
                CHECK(text.find("NumberOfPolys=\"0\"") == std::string::npos);
            const bool same = text == cli_test::read_text(one + f);
            CHECK(same);
        }
    }
}
