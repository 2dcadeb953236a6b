// `mpirun ... clsph run --on-device-failure continue` when a device of rank 1 fails mid-run (its
// Nth kernel launch, injected by the test build clsph-faulty in rank 1's own application context):
// no rank hangs, every rank gives up that step, goes back to the same last checkpoint and goes on
// over the devices left on every rank, and the run ends as the one-process run that loses the same
// device at the same step ends: the same step given up, the same checkpoint, stats.csv byte for
// byte and the last frame bit for bit (by id). Rank 1 loses one of its two devices; rank 1 loses
// its only one and goes on without slabs. CTest runs this program alone (not under mpirun).
#include "mpi_cli_support.hpp"

#include <clsph/io.hpp>

#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <vector>

using namespace mpi_cli_test;

namespace {

// --balance off: cuts from the particle counts alone, so both runs cut alike; a checkpoint every
// 0.002 s, so the failover goes back to one taken mid-run.
const std::vector<std::string> run_args = join(join({"run", scene}, tiny), {"--balance", "off", "--until", "0.01", "--every",
                                                                            "0.0005", "--checkpoint-every", "0.002",
                                                                            "--on-device-failure", "continue"});

// mpiexec -n 1 clsph ARGS : -n 1 env CLSPH_TEST_FAULT=FAULT clsph-faulty ARGS
std::vector<std::string> rank1_faulty(const std::vector<std::string>& args, const std::string& fault) {
    std::vector<std::string> a = {CLSPH_MPIEXEC_NUMPROC_FLAG, "1"};
    for (const char* f : CLSPH_MPIEXEC_FLAGS) a.push_back(f);
    a.push_back(CLSPH_CLI);
    a.insert(a.end(), args.begin(), args.end());
    a.insert(a.end(), {":", CLSPH_MPIEXEC_NUMPROC_FLAG, "1", "env", "CLSPH_TEST_FAULT=" + fault, CLSPH_FAULTY_CLI});
    a.insert(a.end(), args.begin(), args.end());
    return a;
}

// The run across ranks (rank 1's fault) against one process on the same devices (the same
// device's fault): both complete, having given up the same step for the same checkpoint, with the
// same stats and the same last frame.
void same_failover(const std::string& name, const std::string& rank_devices, const std::string& rank1_fault,
                   const std::string& devices, const std::string& fault) {
    const std::string across = work_dir(name), one = work_dir(name + "_one");
    std::string log, log1;
    const int code = run_program(CLSPH_MPIEXEC, rank1_faulty(join(run_args, {"--out", across, "--devices", rank_devices}), rank1_fault), log);
    INFO(log);
    CHECK(code != -1000);  // not a hang ended by the timeout
    REQUIRE(code == 0);
    CHECK(log.find("rank 1: device #") != std::string::npos);
    CHECK(log.find("CL_OUT_OF_RESOURCES") != std::string::npos);
    ::setenv("CLSPH_TEST_FAULT", fault.c_str(), 1);
    const int code1 = cli_test::run_faulty(join(run_args, {"--out", one, "--devices", devices}), log1);
    ::unsetenv("CLSPH_TEST_FAULT");
    INFO(log1);
    REQUIRE(code1 == 0);

    const auto j = read_json(across + "/run.json"), j1 = read_json(one + "/run.json");
    CHECK(j.at("status") == "completed");
    REQUIRE(j.at("resumes").size() == 1);
    REQUIRE(j1.at("resumes").size() == 1);
    CHECK(j.at("resumes")[0].at("step") == j1.at("resumes")[0].at("step"));
    CHECK(j.at("resumes")[0].at("step").get<int>() > 0);  // a checkpoint taken mid-run, not the start's
    const std::string reason = j.at("resumes")[0].at("reason");
    CHECK(reason.find("rank 1: device #") != std::string::npos);
    CHECK(reason.find("failed") != std::string::npos);
    // The step given up: the same in both, named by the failing rank's message.
    const std::string given_up = log1.substr(log1.find("failed: step "), 20);
    CHECK(log.find(given_up) != std::string::npos);
    CHECK(cli_test::read_text(across + "/stats.csv") == cli_test::read_text(one + "/stats.csv"));
    const auto frames = read_pvd(across + "/dam_break.pvd"), frames1 = read_pvd(one + "/dam_break.pvd");
    REQUIRE(frames.size() == frames1.size());
    REQUIRE(!frames.empty());
    CHECK(frames.back().time == frames1.back().time);
    CHECK(same_frame(across + "/" + frames.back().file, one + "/" + frames1.back().file));
}

}  // namespace

TEST_CASE("across ranks, rank 1 losing one of its two devices: every rank goes on, as one process on the devices left") {
    // Three devices: rank 0 drives #0, rank 1 #1 and #2; #2 (rank 1's second) fails at its 500th launch.
    ::setenv("POCL_DEVICES", "pthread pthread pthread", 1);
    same_failover("mpi_failover_one_of_two", "rank0=0;rank1=1,2", "enqueue:500:1", "0,1,2", "enqueue:500:2");
    ::setenv("POCL_DEVICES", "pthread pthread", 1);
}

TEST_CASE("across ranks, rank 1 losing its only device: it goes on without slabs, as one process on the device left") {
    same_failover("mpi_failover_only", "rank0=0;rank1=1", "enqueue:400", "0,1", "enqueue:400:1");
    // After the failover rank 1 holds nothing: its pieces of the last frame are empty.
    const std::string across = std::string(CLSPH_CLI_WORK) + "/mpi_failover_only";
    const auto frames = read_pvd(across + "/dam_break.pvd");
    REQUIRE(!frames.empty());
    const auto sources = read_pvtu_sources(across + "/" + frames.back().file);
    REQUIRE(sources.size() == 2);
    CHECK(read_vtu(across + "/" + sources[1]).size() == 0);
    CHECK(read_vtu(across + "/" + sources[0]).size() == read_vtu(across + "/" + frames.front().file).size());
    const auto j = read_json(across + "/run.json");
    const std::string devices = j.at("resumes")[0].at("devices").dump();
    CHECK(devices.find("rank 0: ") != std::string::npos);
    CHECK(devices.find("rank 1: ") == std::string::npos);
}
