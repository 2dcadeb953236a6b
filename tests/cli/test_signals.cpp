// Runs stopped from outside: the test starts the tool, signals it mid-run (SIGTERM, two Ctrl-Cs,
// SIGKILL) and reads every file back: what docs/cli.md promises is on disk.
#include "support.hpp"

#include <cstdio>

#include <doctest/doctest.h>

#include <chrono>
#include <csignal>
#include <thread>

using namespace cli_test;

namespace {

// Starts a long run of the tiny dam break (frames every 0.001 s) and waits until `frames` frames
// are listed in the .pvd.
std::unique_ptr<Process> start_long_run(const std::string& out, const std::string& log, std::size_t frames) {
    fs::create_directories(CLSPH_CLI_WORK);
    auto p = std::make_unique<Process>(CLSPH_CLI, args({{"run", scene}, tiny, {"--until", "10", "--every", "0.001", "--out", out}}), log);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    while (std::chrono::steady_clock::now() < deadline) {
        if (fs::exists(out + "/dam_break.pvd") && clsph::read_pvd(out + "/dam_break.pvd").size() >= frames) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return p;
}

// Every frame the .pvd lists is whole; stats.csv and the probe files have whole rows and reach at
// least the last frame listed. Returns the last frame's time.
double check_files_up_to_last_frame(const std::string& out) {
    const auto pvd = clsph::read_pvd(out + "/dam_break.pvd");
    REQUIRE(pvd.size() >= 2);
    const std::size_t particles = tiny_count().total;
    for (const auto& f : pvd) {
        CAPTURE(f.file);
        CHECK(clsph::read_vtu(out + "/" + f.file).size() == particles);
    }
    const double last = pvd.back().time;
    const auto stats = read_csv_rows(out + "/stats.csv");
    REQUIRE(stats.size() >= 2);
    for (std::size_t r = 1; r < stats.size(); ++r) CHECK(stats[r].size() == stats[0].size());  // whole rows (9 columns)
    CHECK(std::stod(stats.back()[1]) >= last * (1 - 1e-8));  // stats.csv's times have 9 significant digits
    for (const char* name : {"p_column_base", "p_far_wall", "h_column", "h_middle"}) {
        CAPTURE(name);
        const auto rows = read_csv_rows(out + "/probe_" + std::string(name) + ".csv");
        REQUIRE(rows.size() >= 2);  // the header and at least the sample at t = 0
        for (std::size_t r = 1; r < rows.size(); ++r) CHECK(rows[r].size() == 2);
    }
    return last;
}

}  // namespace

TEST_CASE("SIGTERM ends the run like Ctrl-C: a final frame, complete files, exit 143") {
    const std::string out = work_dir("sigterm");
    const std::string log = std::string(CLSPH_CLI_WORK) + "/sigterm.log";
    auto p = start_long_run(out, log, 3);
    p->signal(SIGTERM);
    const int code = p->wait();
    INFO(read_text(log));
    CHECK(code == 143);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "interrupted");
    CHECK(j.at("signal") == "SIGTERM");
    CHECK(j.at("exit_status") == 143);
    const double last = check_files_up_to_last_frame(out);
    // The final frame is where the run stopped: the last row of stats.csv, as run.json says.
    const auto stats = read_csv_rows(out + "/stats.csv");
    CHECK(std::abs(last - std::stod(stats.back()[1])) < 1e-9);
    CHECK(j.at("steps").get<std::uint64_t>() == std::stoull(stats.back()[0]));
    CHECK(read_text(log).find("clsph: interrupted at t = ") != std::string::npos);
    // A checkpoint where it stopped, and clsph resume goes on from it: rows without gap or repeat.
    const auto steps = j.at("steps").get<unsigned long long>();
    char name[64];
    std::snprintf(name, sizeof name, "/checkpoint_%05llu.clsph", steps);
    CHECK(fs::exists(out + name));
    std::string resumed;
    CHECK(run({"resume", out, "--steps", "3"}, resumed) == 0);
    const auto after = read_csv_rows(out + "/stats.csv");
    for (std::size_t r = 1; r < after.size(); ++r) CHECK(std::stoull(after[r][0]) == r - 1);
    CHECK(std::stoull(after.back()[0]) == steps + 3);
}

TEST_CASE("Ctrl-C twice: the run ends at once and run.json still says how") {
    const std::string out = work_dir("sigint_twice");
    const std::string log = std::string(CLSPH_CLI_WORK) + "/sigint_twice.log";
    auto p = start_long_run(out, log, 3);
    p->interrupt();
    std::this_thread::sleep_for(std::chrono::milliseconds(3));  // two at once would merge into one
    p->interrupt();  // milliseconds later: before the clean stop has finished
    const int code = p->wait();
    INFO(read_text(log));
    CHECK(code == 130);
    const auto j = read_json(out + "/run.json");
    const std::string status = j.at("status");
    // "aborted" when the second arrived before the clean stop finished (as a rule, 3 ms later), else the
    // clean stop's "interrupted"; never "running".
    CHECK((status == "aborted" || status == "interrupted"));
    if (status == "aborted") CHECK(j.at("message").get<std::string>().find("second Ctrl-C") != std::string::npos);
    check_files_up_to_last_frame(out);
    CHECK_FALSE(fs::exists(out + "/run.json.abort"));
}

TEST_CASE("kill -9: every frame listed is whole, stats and probes reach the last of them") {
    const std::string out = work_dir("sigkill");
    const std::string log = std::string(CLSPH_CLI_WORK) + "/sigkill.log";
    auto p = start_long_run(out, log, 4);
    p->signal(SIGKILL);
    CHECK(p->wait() == -SIGKILL);
    // Nothing could say how the run ended: run.json is the one written at the start, whole.
    CHECK(read_json(out + "/run.json").at("status") == "running");
    check_files_up_to_last_frame(out);
}
