// `clsph run` end to end on a tiny dam break (L/dp = 10, c0 = 10 sqrt(gH), 6,305 particles, ~30
// steps) on the default devices, and on bad input: what exit status, what message, what on disk.
#include "support.hpp"

#include <clsph/io.hpp>
#include <doctest/doctest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace cli_test;

TEST_CASE("scenes/channel.json: stats.csv counts what the inlet made and the outlet removed") {
    // dp 0.02: 12 particles a layer, a layer every 0.067 s at 0.3 m/s; the first water leaves at 1 m
    // after about 0.07 s.
    const std::string out = work_dir("channel");
    std::string log;
    const int code = run(args({{"run", source + "/scenes/channel.json", "--devices", "0", "--set", "physics.dp=0.02", "--until", "0.2", "--every",
                                "0.2", "--force", "--out", out}}),
                         log);
    INFO(log);
    REQUIRE(code == 0);
    const auto stats = read_csv_rows(out + "/stats.csv");
    REQUIRE(stats.size() >= 3);
    REQUIRE(stats[0].back() == "created");
    const std::size_t first = std::stoull(stats[1][3]), buffer = std::stoull(stats[1][8]), gone = std::stoull(stats[1][5]);
    CHECK(buffer == 4 * 12);  // the inlet's box at the start
    for (std::size_t r = 2; r < stats.size(); ++r) {
        const std::size_t created = std::stoull(stats[r][8]), removed = std::stoull(stats[r][5]);
        CHECK(created >= std::stoull(stats[r - 1][8]));
        CHECK(std::stoull(stats[r][3]) == first + (created - buffer) - (removed - gone));  // the count follows both
    }
    const std::size_t made = std::stoull(stats.back()[8]) - buffer;
    CHECK(made == 12 * static_cast<std::size_t>(std::floor(0.3 * std::stod(stats.back()[1]) / 0.02)));
    CHECK(std::stoull(stats.back()[5]) > 0);
    CHECK(log.find("created") != std::string::npos);
}

TEST_CASE("a tiny dam break: exit 0 and a consistent output directory") {
    const std::string out = work_dir("dam_break");
    // --force clears what an earlier run left and nothing else.
    fs::create_directories(out);
    std::ofstream(out + "/frame_00099.vtu") << "stale";
    std::ofstream(out + "/last_good.vtu") << "an earlier run's failure";
    std::ofstream(out + "/keep.txt") << "the user's";
    std::string log;
    const int code = run(args({{"run", scene}, tiny, {"--until", "0.01", "--every", "0.005", "--csv", "--force", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    CHECK(log.find("completed") != std::string::npos);
    CHECK(fs::exists(out + "/keep.txt"));
    CHECK_FALSE(fs::exists(out + "/frame_00099.vtu"));
    CHECK_FALSE(fs::exists(out + "/last_good.vtu"));  // this run did not fail: no last good state of another's

    // The collection: one entry per frame file, at 0, 0.005 and 0.01 s.
    const auto pvd = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(pvd.size() == 3);
    CHECK(count_files(out, "frame_", ".vtu") == pvd.size());
    CHECK(count_files(out, "frame_", ".csv") == pvd.size());
    const double times[] = {0.0, 0.005, 0.01};
    std::size_t particles = 0;
    for (std::size_t k = 0; k < pvd.size(); ++k) {
        CAPTURE(k);
        CHECK(near(pvd[k].time, times[k]));
        const auto vtu = clsph::read_vtu(out + "/" + pvd[k].file);
        const auto csv = clsph::read_csv(out + "/" + fs::path(pvd[k].file).replace_extension(".csv").string());
        REQUIRE(vtu.size() > 0);
        CHECK(vtu.size() == csv.size());
        CHECK(by_id(vtu) == by_id(csv));
        if (k == 0) particles = vtu.size();
        CHECK(vtu.size() == particles);  // nothing leaves the tank this early
    }

    // stats.csv: a row for the initial state and one per step, ending at --until.
    const auto stats = read_csv_rows(out + "/stats.csv");
    REQUIRE(stats.size() >= 3);
    CHECK(stats[0] == std::vector<std::string>{"step", "time", "dt", "particles", "fluid", "removed", "kinetic_energy", "max_speed", "created"});
    for (std::size_t r = 1; r < stats.size(); ++r) {
        REQUIRE(stats[r].size() == 9);
        CHECK(stats[r][8] == "0");  // no inlet
        CHECK(std::stoull(stats[r][0]) == r - 1);
        CHECK(std::stoull(stats[r][3]) == particles);
    }
    const std::uint64_t steps = stats.size() - 2;
    CHECK(near(std::stod(stats.back()[1]), 0.01));

    // A probe file per probe: the initial sample and one every run.probe_every (10) steps.
    for (const char* name : {"p_column_base", "p_far_wall", "h_column", "h_middle"}) {
        CAPTURE(name);
        const auto rows = read_csv_rows(out + "/probe_" + name + ".csv");
        REQUIRE(rows.size() >= 2);
        CHECK(rows[0] == std::vector<std::string>{"time", "value"});
        CHECK(rows.size() - 1 == 1 + steps / 10);
    }
    // The column-base pressure is roughly hydrostatic, rho g (2L - z): ~2.7 kPa.
    const auto base = read_csv_rows(out + "/probe_p_column_base.csv");
    CHECK(std::stod(base[1][1]) > 1500.0);
    CHECK(std::stod(base[1][1]) < 4000.0);

    // run.json: provenance that parses, and agrees with the files.
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "completed");
    CHECK(!j.at("clsph_version").get<std::string>().empty());
    CHECK(!j.at("start_time").get<std::string>().empty());
    CHECK(j.at("devices").size() >= 1);
    // The order within cells, left to auto: morton where every device ran lanes.
    const auto forms = j.at("interaction").get<std::vector<std::string>>();
    const bool all_lanes = !forms.empty() && std::all_of(forms.begin(), forms.end(), [](const std::string& f) { return f == "lanes"; });
    CHECK(j.at("cell_order") == (all_lanes ? "morton" : "arrival"));
    CHECK(j.at("steps").get<std::uint64_t>() == steps);
    CHECK(j.at("particles").get<std::size_t>() == particles);
    CHECK(j.at("scene").at("physics").at("dp").get<double>() == doctest::Approx(0.0146));
    CHECK(j.at("scene").at("name") == "dam_break");
    const auto cmd = j.at("command_line").get<std::vector<std::string>>();
    CHECK(std::find(cmd.begin(), cmd.end(), "--csv") != cmd.end());
}

TEST_CASE("--steps stops after N steps with a final frame where it stopped") {
    const std::string out = work_dir("steps");
    std::string log;
    const int code = run(args({{"run", scene}, tiny, {"--steps", "3", "--every", "1", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    const auto pvd = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(pvd.size() == 2);  // t = 0 and where step 3 ended
    const auto stats = read_csv_rows(out + "/stats.csv");
    REQUIRE(stats.size() == 5);
    CHECK(near(pvd[1].time, std::stod(stats.back()[1])));
    CHECK(read_json(out + "/run.json").at("steps") == 3);
    CHECK_FALSE(fs::exists(out + "/frame_00000.csv"));  // no --csv
}

TEST_CASE("run.list_buffer: the summary and run.json say how often the cell tables were built") {
    const std::string out = work_dir("list_buffer");
    std::string log;
    const int code = run(args({{"run", scene}, tiny, {"--set", "run.list_buffer=0.2", "--steps", "60", "--every", "1", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    const auto at = log.find("cell tables: built ");
    REQUIRE(at != std::string::npos);
    const std::size_t builds = std::stoul(log.substr(at + 19));
    CHECK(log.find("in 60 steps", at) != std::string::npos);
    const auto run_json = read_json(out + "/run.json");
    CHECK(run_json.at("table_builds") == builds);
    CHECK(builds >= 1);
    CHECK(builds < 30);  // kept over steps: the tiny dam break moves a few mm in 60 steps
    CHECK(run_json.at("scene").at("run").at("list_buffer") == 0.2);
}

TEST_CASE("the summary and run.json say how many steps ran ahead of the host") {
    // One device (the first: steps ahead on any device with fp64), tables kept with a buffer small
    // enough for several builds in 60 steps: the builds after the first (set-up) are the steps
    // waited for, every other step runs ahead. With --synchronous none does.
    for (const bool synchronous : {false, true}) {
        CAPTURE(synchronous);
        const std::string out = work_dir(synchronous ? "ahead_sync" : "ahead");
        std::vector<std::string> more = {"--devices", "0", "--set", "run.list_buffer=0.02", "--steps", "60", "--every", "1", "--out", out};
        if (synchronous) more.push_back("--synchronous");
        std::string log;
        const int code = run(args({{"run", scene}, tiny, more}), log);
        INFO(log);
        REQUIRE(code == 0);
        const auto run_json = read_json(out + "/run.json");
        const std::size_t builds = run_json.at("table_builds").get<std::size_t>();
        const std::size_t ahead = run_json.at("steps_ahead").get<std::size_t>();
        if (synchronous) {
            CHECK(ahead == 0);
            CHECK(log.find("steps ahead of the host: none") != std::string::npos);
            continue;
        }
        CHECK(builds > 2);
        CHECK(ahead + (builds - 1) == 60);
        CHECK(log.find("steps ahead of the host: " + std::to_string(ahead) + " of 60") != std::string::npos);
    }
}

TEST_CASE("Ctrl-C ends the run after a whole step, with a final frame") {
    const std::string out = work_dir("interrupted");
    fs::create_directories(CLSPH_CLI_WORK);
    const std::string log = std::string(CLSPH_CLI_WORK) + "/interrupted.log";
    cli_test::Process p(CLSPH_CLI, args({{"run", scene}, tiny, {"--until", "10", "--out", out}}), log);
    // Wait for a few steps in stats.csv (after set-up and kernel builds), then interrupt.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    while (read_csv_rows(out + "/stats.csv").size() < 5 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    p.interrupt();
    const int code = p.wait();
    INFO(cli_test::read_text(log));
    CHECK(code == 130);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "interrupted");
    const auto stats = read_csv_rows(out + "/stats.csv");
    const auto pvd = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(pvd.size() >= 2);
    CHECK(near(pvd.back().time, std::stod(stats.back()[1])));
    CHECK(clsph::read_vtu(out + "/" + pvd.back().file).size() > 0);
}

TEST_CASE("a blow-up: exit 2, the error named, the last good state written") {
    const std::string out = work_dir("blow_up");
    std::string log;
    // The column thrown at the wall behind it at 20 m/s: the wall's density leaves its band in a few steps.
    const int code = run(args({{"run", scene}, tiny, {"--set", "fluid[0].velocity=[-20,0,0]", "--until", "0.01", "--out", out}}), log);
    INFO(log);
    CHECK(code == 2);
    CHECK(log.find("clsph: error: step ") != std::string::npos);
    CHECK(log.find("outside the allowed band") != std::string::npos);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "failed");
    CHECK(j.at("message").get<std::string>().find("outside the allowed band") != std::string::npos);
    CHECK(clsph::read_vtu(out + "/last_good.vtu").size() == tiny_count({"fluid[0].velocity=[-20,0,0]"}).total);
    CHECK(clsph::read_pvd(out + "/dam_break.pvd").size() >= 1);
}

TEST_CASE("--dry-run reports and writes nothing") {
    const std::string out = work_dir("dry_run");
    std::string log;
    const int code = run(args({{"run", scene}, tiny, {"--dry-run", "--csv", "--out", out}}), log);
    INFO(log);
    CHECK(code == 0);
    const TinyCount n = tiny_count();
    CHECK(n.fluid > 0);
    CHECK(n.boundary > 0);
    const std::string counts = "particles: " + std::to_string(n.total) + " (" + std::to_string(n.fluid) + " fluid, " +
                               std::to_string(n.boundary) + " boundary)";
    CAPTURE(counts);
    CHECK(log.find(counts) != std::string::npos);
    CHECK(log.find("first time step") != std::string::npos);
    CHECK(log.find("output (estimate)") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

// A scene far too large for the device: stopped by the memory plan before any buffer is made,
// with physics.dp and each device's need and memory named. The devices are pocl's with their
// memory limited to 1 GiB (POCL_MEMORY_LIMIT), so the real scene (the tiny tank at dp 0.7 mm,
// about 24 M particles, some 1.5 GiB a device) fails as it would on a full device.
TEST_CASE("a scene too large for the devices: exit 1 before allocating, naming physics.dp") {
    const std::string out = work_dir("too_large");
    std::vector<std::string> big = tiny;
    big[1] = "physics.dp=0.0007";
    ::setenv("POCL_MEMORY_LIMIT", "1", 1);
    for (const bool dry : {false, true}) {
        CAPTURE(dry);
        std::string log;
        std::vector<std::string> a = args({{"run", scene}, big, {"--devices", "platform:pocl", "--out", out}});
        if (dry) a.push_back("--dry-run");
        const int code = run(a, log, 300.0);
        INFO(log);
        CHECK(code == 1);
        CHECK(log.find("physics.dp = 0.0007: the scene needs") != std::string::npos);
        CHECK(log.find("which has 1 GiB") != std::string::npos);
        CHECK(log.find("remain (") == std::string::npos);  // not the tracker's refusal of one buffer
        CHECK(log.find("setting up the devices") == std::string::npos);
        CHECK_FALSE(fs::exists(out));
        if (dry) CHECK(log.find("DOES NOT FIT") != std::string::npos);
    }
    ::unsetenv("POCL_MEMORY_LIMIT");
}

TEST_CASE("--dry-run: the memory plan first, then the measured peak within 2 % of it") {
    const std::string out = work_dir("dry_run_plan");
    std::string log;
    // One device: with several, --balance dynamic's calibration sizes the stores by its samples.
    const int code = run(args({{"run", scene}, tiny, {"--dry-run", "--devices", "0", "--out", out}}), log);
    INFO(log);
    REQUIRE(code == 0);
    const auto plan = log.find("memory plan (predicted on the host, nothing allocated)");
    const auto measured = log.find("measured: setting up the devices");
    REQUIRE(plan != std::string::npos);
    REQUIRE(measured != std::string::npos);
    CHECK(plan < measured);
    for (const char* name : {"particles: positions", "neighbour ranges", "radix sort digit counts", "reorder scratch",
                             "CL_DEVICE_MAX_MEM_ALLOC_SIZE", "CL_DEVICE_GLOBAL_MEM_SIZE", "the largest scene"})
        CHECK(log.find(name, plan) < measured);
    // A line per device: "...: N particles, peak X of device memory (...); predicted Y (+0.12 %)".
    std::istringstream lines(log.substr(measured));
    std::size_t devices = 0;
    for (std::string line; std::getline(lines, line);) {
        if (line.find(", peak ") == std::string::npos || line.find("; predicted ") == std::string::npos) continue;
        const auto open = line.rfind('('), close = line.rfind(" %)");
        REQUIRE(open != std::string::npos);
        REQUIRE(close != std::string::npos);
        const double error = std::stod(line.substr(open + 1, close - open - 1));
        CAPTURE(line);
        CHECK(std::abs(error) < 2.0);
        ++devices;
    }
    CHECK(devices >= 1);
}

TEST_CASE("an existing output directory is refused without --force, and left alone") {
    const std::string out = work_dir("existing");
    fs::create_directories(out);
    std::ofstream(out + "/keep.txt") << "the user's";
    std::string log;
    const int code = run(args({{"run", scene}, tiny, {"--steps", "1", "--out", out}}), log);
    INFO(log);
    CHECK(code == 1);
    CHECK(log.find("--force") != std::string::npos);
    CHECK(fs::exists(out + "/keep.txt"));
    CHECK(std::distance(fs::directory_iterator(out), fs::directory_iterator{}) == 1);
}

TEST_CASE("bad input: exit 1, a message naming the file and key, no output directory") {
    const std::string out = work_dir("bad");
    struct Case {
        std::vector<std::string> args;
        std::string expected;  // in the message, after "clsph: error: "
    };
    const std::string corpus = source + "/tests/scene/corpus/";
    std::vector<Case> cases = {
        {{"run", corpus + "wrong_type_dp.json"}, corpus + "wrong_type_dp.json: physics.dp: expected a number"},
        {{"run", corpus + "fluid_max_two_numbers.json"}, corpus + "fluid_max_two_numbers.json: fluid[1].max: expected 3 numbers"},
        {{"run", corpus + "truncated.json"}, corpus + "truncated.json: "},
        {{"run", scene, "--set", "physics.dq=1"}, scene + ": physics.dq: unknown key"},
        {{"run", scene, "--set", "physics.dp=0"}, scene + ": physics.dp: must be a positive number"},
        // Found while setting up the grid, not by the scene reader: still names the file.
        {{"run", scene, "--set", "physics.dp=0.02"}, scene + ": domain: periodic axis y"},
        {{"run", source + "/scenes/no_such_scene.json"}, source + "/scenes/no_such_scene.json: cannot read"},
        {{"run", scene, "--every", "0"}, "--every"},
        {{"run", scene, "--set", "run.list_buffer=2"}, scene + ": run.list_buffer: must be a fraction"},
        // Found while setting up the devices: still before any output.
        {{"run", scene, "--set", "run.list_buffer=0.1", "--set", "physics.integrator=symplectic"},
         scene + ": run.list_buffer: tables kept over steps are not supported with the Symplectic integrator"},
    };
    // Every file of the malformed-scene corpus (tests/scene/test_corpus.cpp checks each message).
    for (const auto& e : fs::directory_iterator(corpus))
        if (e.path().filename() != "valid_base.json") cases.push_back({{"run", e.path().string()}, e.path().string() + ": "});
    for (auto& c : cases) {
        c.args.insert(c.args.end(), {"--out", out});
        std::string log;
        const int code = run(c.args, log);
        CAPTURE(c.args[1]);
        INFO(log);
        CHECK(code == 1);
        CHECK(log.find("clsph: error: " + c.expected) != std::string::npos);
        CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("clsph run --help: exit 0, the options grouped by topic, each saying its default") {
    std::string help;
    const int code = run({"run", "--help"}, help);
    INFO(help);
    REQUIRE(code == 0);
    std::size_t at = 0;
    for (const char* group : {"Scene", "Devices", "Time and steps", "Output", "Images and surfaces",
                              "Checkpoints and failures", "Balance and profiling", "MPI"}) {
        CAPTURE(group);
        const auto found = help.find("\n" + std::string(group) + ":\n", at);
        REQUIRE(found != std::string::npos);  // listed, and after the groups before it
        at = found;
    }
    // Each option's entry (its line, and the lines its description wraps onto) says its default.
    std::istringstream lines(help);
    std::vector<std::string> entries;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("  -", 0) == 0)
            entries.push_back(line);
        else if (!entries.empty() && line.rfind("    ", 0) == 0)
            entries.back() += line;
        else if (!entries.empty() && line.empty())
            entries.emplace_back();  // a blank line ends the entry
    }
    std::size_t options = 0;
    for (const auto& e : entries) {
        if (e.empty() || e.find("--help") != std::string::npos) continue;
        CAPTURE(e);
        CHECK(e.find("default") != std::string::npos);
        ++options;
    }
    CHECK(options >= 20);  // the entries were found (29 options when this was written)
}
