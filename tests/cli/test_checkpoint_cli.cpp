// clsph run --checkpoint-every and clsph resume end to end on the tiny dam break: a run stopped at
// a checkpoint and resumed leaves the same files as one run straight through (stats, probes and
// frames byte for byte, on one device); a corrupt, truncated or foreign checkpoint is refused by
// name with the reason; resumed onto other devices, the same particles within round-off.
#include "support.hpp"

#include <clsph/io.hpp>
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace fs = std::filesystem;
using namespace cli_test;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void spit(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// A run to t = 0.01 with checkpoints at 0.005 and 0.01 (steps 15 and 30 of ~60).
void first_half(const std::string& out, const std::vector<std::string>& more = {}) {
    std::string log;
    const int code = run(args({{"run", scene}, tiny,
                               {"--devices", "0", "--until", "0.01", "--every", "0.005", "--csv", "--out", out,
                                "--checkpoint-every", "0.005"},
                               more}),
                         log);
    INFO(log);
    REQUIRE(code == 0);
}

}  // namespace

TEST_CASE("run to a checkpoint, then clsph resume: the same stats, probes and frames as one run straight") {
    const std::string straight = work_dir("ckpt_straight"), split = work_dir("ckpt_split");
    std::string log;
    REQUIRE(run(args({{"run", scene}, tiny, {"--devices", "0", "--until", "0.02", "--every", "0.005", "--csv", "--out", straight}}),
                log) == 0);
    first_half(split);
    CHECK(count_files(split, "checkpoint_", ".clsph") == 2);
    const int code = run({"resume", split, "--until", "0.02"}, log);
    INFO(log);
    REQUIRE(code == 0);
    CHECK(log.find("resuming " + split + " from " + split + "/checkpoint_") != std::string::npos);
    for (const auto& e : fs::directory_iterator(straight)) {
        const std::string name = e.path().filename().string();
        if (e.path().extension() != ".csv") continue;
        INFO(name);
        CHECK(slurp(straight + "/" + name) == slurp(split + "/" + name));
    }
    const auto a = clsph::read_pvd(straight + "/dam_break.pvd"), b = clsph::read_pvd(split + "/dam_break.pvd");
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) CHECK(a[i].time == b[i].time);
    const auto j = read_json(split + "/run.json");
    CHECK(j.at("status") == "completed");
    CHECK(j.at("steps") == read_json(straight + "/run.json").at("steps"));
    REQUIRE(j.at("resumes").size() == 1);
    CHECK(j.at("resumes")[0].at("step") == 30);
    CHECK(j.at("command_line")[1] == "run");
    // The last K (3) checkpoints are kept: 15, 30, 45, 60 written.
    CHECK(count_files(split, "checkpoint_", ".clsph") == 3);
}

TEST_CASE("a flipped byte, a truncated file, another scene's checkpoint: refused, naming the file and the reason") {
    const std::string out = work_dir("ckpt_refused");
    first_half(out);
    const std::string newest = out + "/checkpoint_00030.clsph", older = out + "/checkpoint_00015.clsph";
    std::string good = slurp(newest), flipped = good;
    flipped[flipped.size() / 2] ^= 0x20;
    spit(newest, flipped);
    std::string log;
    int code = run({"resume", out, "--until", "0.01"}, log);
    CHECK(log.find("refusing checkpoint " + newest + ": corrupt (checksum mismatch)") != std::string::npos);
    // It goes on from the older one.
    CHECK(code == 0);
    CHECK(log.find("from " + older) != std::string::npos);

    const std::string ckpt_dir = work_dir("ckpt_refused_truncated");
    first_half(ckpt_dir);
    for (const auto& e : fs::directory_iterator(ckpt_dir))
        if (e.path().extension() == ".clsph") fs::resize_file(e.path(), fs::file_size(e.path()) / 2);
    code = run({"resume", ckpt_dir}, log);
    INFO(log);
    CHECK(code == 1);
    CHECK(log.find("checkpoint " + ckpt_dir + "/checkpoint_00030.clsph: truncated") != std::string::npos);

    const std::string other = work_dir("ckpt_refused_other");
    first_half(other, {"--set", "physics.coefsound=12"});
    const std::string mine = work_dir("ckpt_refused_mine");
    first_half(mine);
    for (const auto& e : fs::directory_iterator(mine))
        if (e.path().extension() == ".clsph") fs::remove(e.path());
    std::string foreign;  // the other scene's steps differ: whatever name its checkpoint has
    for (const auto& e : fs::directory_iterator(other))
        if (e.path().extension() == ".clsph") foreign = e.path().filename().string();
    REQUIRE(!foreign.empty());
    fs::copy_file(other + "/" + foreign, mine + "/" + foreign);
    code = run({"resume", mine}, log);
    CHECK(code == 1);
    CHECK(log.find("checkpoint " + mine + "/" + foreign + ": written for another scene") != std::string::npos);
}

TEST_CASE("resumed onto another device set: the same particles, positions within round-off") {
    const std::string straight = work_dir("ckpt_moved_straight"), moved = work_dir("ckpt_moved");
    std::string log;
    REQUIRE(run(args({{"run", scene}, tiny, {"--devices", "0", "--until", "0.015", "--every", "0.005", "--out", straight}}),
                log) == 0);
    first_half(moved);
    const int code = run({"resume", moved, "--until", "0.015", "--devices", "all"}, log);
    INFO(log);
    REQUIRE(code == 0);
    const auto a = by_id(clsph::read_vtu(straight + "/frame_00003.vtu"));
    const auto b = by_id(clsph::read_vtu(moved + "/frame_00003.vtu"));
    REQUIRE(a.size() == b.size());
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        REQUIRE(a[i].first == b[i].first);
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[i].second[k] - b[i].second[k]));
    }
    CHECK(worst < 1e-4);
}

// CTest runs this case alone as cli_resume_multi, with POCL_DEVICES="pthread pthread pthread".
TEST_CASE("three devices of one implementation: resume leaves the straight run's stats, probes and frames") {
    const std::string straight = work_dir("ckpt3_straight"), split = work_dir("ckpt3_split");
    std::string log;
    // Static cuts: the balancer's dynamic cuts follow measured times, so two straight runs would
    // already sum the kinetic energy over different slabs.
    const std::vector<std::string> common = {"--devices", "all", "--balance", "static", "--every", "0.005", "--csv"};
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--until", "0.02", "--out", straight}}), log) == 0);
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--until", "0.01", "--out", split, "--checkpoint-every", "0.01"}}), log) == 0);
    const int code = run({"resume", split, "--until", "0.02"}, log);
    INFO(log);
    REQUIRE(code == 0);
    for (const auto& e : fs::directory_iterator(straight)) {
        const std::string name = e.path().filename().string();
        if (e.path().extension() != ".csv") continue;
        INFO(name);
        CHECK(slurp(straight + "/" + name) == slurp(split + "/" + name));
    }
}

// Also under cli_resume_multi (three pocl devices): the middle device fails at its 300th launch
// (step 8); with continue the run goes back to its last checkpoint and finishes on two.
TEST_CASE("three devices, a device failing mid-run: continue finishes on two, stop exits 3") {
    const std::vector<std::string> common = {"--devices", "all", "--balance", "off", "--until", "0.01", "--every", "0.0005"};
    SUBCASE("continue") {
        const std::string out = work_dir("failover_continue");
        ::setenv("CLSPH_TEST_FAULT", "enqueue:300:1", 1);
        std::string log;
        const int code = run_faulty(args({{"run", scene}, tiny, common, {"--out", out, "--on-device-failure", "continue"}}), log);
        ::unsetenv("CLSPH_TEST_FAULT");
        INFO(log);
        REQUIRE(code == 0);
        CHECK(log.find("--on-device-failure continue: going back to the last checkpoint on devices 0,2") != std::string::npos);
        const auto j = read_json(out + "/run.json");
        CHECK(j.at("status") == "completed");
        CHECK(j.at("devices").size() == 2);
        REQUIRE(j.at("resumes").size() == 1);
        CHECK(j.at("resumes")[0].at("reason").get<std::string>().find("failed") != std::string::npos);
        // Every particle exactly once in the last frame, the collection without a gap.
        const auto pvd = clsph::read_pvd(out + "/dam_break.pvd");
        REQUIRE(pvd.size() == frames_implied(0.01, 0.0005));  // common's --until and --every
        for (std::size_t i = 0; i < pvd.size(); ++i) CHECK(near(pvd[i].time, 0.0005 * static_cast<double>(i)));
        const auto last = by_id(clsph::read_vtu(out + "/" + pvd.back().file));
        REQUIRE(last.size() == tiny_count().total);
        for (std::size_t i = 1; i < last.size(); ++i) CHECK(last[i].first != last[i - 1].first);
        // stats.csv: one row per step, in order.
        const auto rows = read_csv_rows(out + "/stats.csv");
        for (std::size_t i = 1; i < rows.size(); ++i) CHECK(std::stoull(rows[i][0]) == i - 1);
    }
    SUBCASE("stop (the default)") {
        const std::string out = work_dir("failover_stop");
        ::setenv("CLSPH_TEST_FAULT", "enqueue:300:1", 1);
        std::string log;
        const int code = run_faulty(args({{"run", scene}, tiny, common, {"--out", out}}), log);
        ::unsetenv("CLSPH_TEST_FAULT");
        CHECK(code == 3);
        CHECK(read_json(out + "/run.json").at("status") == "failed");
        CHECK(clsph::read_vtu(out + "/last_good.vtu").size() == tiny_count().total);
    }
}

TEST_CASE("--no-checkpoint: a run leaves no checkpoint, and refuses the options that need one") {
    const std::string out = work_dir("no_checkpoint");
    std::string log;
    int code = run(args({{"run", scene}, tiny, {"--devices", "0", "--steps", "5", "--out", out, "--no-checkpoint"}}), log);
    INFO(log);
    REQUIRE(code == 0);
    std::size_t checkpoints = 0, frames = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        checkpoints += e.path().extension() == ".clsph";
        frames += e.path().extension() == ".vtu";
    }
    CHECK(checkpoints == 0);
    CHECK(frames >= 1);
    code = run(args({{"run", scene}, tiny, {"--devices", "0", "--steps", "5", "--out", out, "--force", "--no-checkpoint",
                                            "--checkpoint-every", "0.005"}}),
               log);
    CHECK(code != 0);
    CHECK(log.find("--no-checkpoint") != std::string::npos);
    code = run(args({{"run", scene}, tiny, {"--devices", "0", "--steps", "5", "--out", out, "--force", "--no-checkpoint",
                                            "--on-device-failure", "continue"}}),
               log);
    CHECK(code != 0);
    CHECK(log.find("--no-checkpoint with --on-device-failure continue") != std::string::npos);
}
