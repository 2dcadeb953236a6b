// Hostile command lines and scenes (issue 14): each answers within seconds with exit status 1 and
// a message naming the option or the file and key; nothing is written; memory stays bounded.
#include "support.hpp"

#include <doctest/doctest.h>

#include <sys/resource.h>

using namespace cli_test;

namespace {

struct Case {
    std::vector<std::string> args;
    std::string expected;  // in the output, after "clsph: error: "
};

}  // namespace

TEST_CASE("hostile options and values: exit 1 within seconds, named, nothing written") {
    const std::string out = work_dir("hostile");
    const std::string obj_dir = std::string(CLSPH_CLI_WORK) + "/hostile_meshes";
    fs::create_directories(obj_dir);
    std::ofstream(obj_dir + "/nan.obj") << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::vector<Case> cases = {
        {{"run", scene, "--until", "inf"}, "--until: expected a finite simulated time >= 0 s"},
        {{"run", scene, "--until", "nan"}, "--until: expected a finite simulated time >= 0 s"},
        {{"run", scene, "--steps", "-5"}, "--steps: expected a whole number of steps from 1 to 1000000000000, got '-5'"},
        {{"run", scene, "--steps", "99999999999999999999999"}, "--steps: expected a whole number of steps"},
        {{"run", scene, "--steps", "18446744073709551617"}, "--steps: expected a whole number of steps"},
        {{"run", scene, "--every", "1e-300"}, "--every: 1e-300 s would write more than a million frames up to run.end_time"},
        {{"run", scene, "--set", "run.end_time=1e300"}, scene + ": run.output_every: 0.01 s would write more than a million frames up to run.end_time = 1e+300 s"},
        {{"run", scene, "--set", "run.output_every=1e-300"}, scene + ": run.output_every: 1e-300 s would write more than a million frames"},
        {{"run", scene, "--set", "physics.coefsound=-1"}, scene + ": physics.coefsound: must be a positive number"},
        {{"run", scene, "--set", "physics.hdp=0.4"}, scene + ": physics.hdp: the kernel support"},
        {{"run", scene, "--set", "domain.periodic=[true,true,false]"}, scene + ": boundaries.walls[0].faces: face x- is on the periodic axis x"},
        {{"run", scene, "--set", "fluid[0].max=[0.001,0.001,0.001]"}, scene + ": fluid[0]: no fluid particle is left in the block"},
        {{"run", scene, "--set", "boundaries.meshes=[{\"path\":\"/dev/zero\"}]"}, scene + ": boundaries.meshes[0].path: cannot read \"/dev/zero\": it is not a regular file"},
        {{"run", scene, "--set", "boundaries.meshes=[{\"path\":\"" + obj_dir + "/nan.obj\"}]"}, scene + ": boundaries.meshes[0].path: " + obj_dir + "/nan.obj: line 2: vertex coordinate 'nan' is not a finite number"},
        {{"run", "/dev/zero"}, "/dev/zero: cannot read: it is not a regular file (a device, a pipe or a socket)"},
        {{"run", std::string(CLSPH_CLI_WORK)}, std::string(CLSPH_CLI_WORK) + ": cannot read: it is a directory, not a file"},
        // Command-line mistakes are bad input like any other: 1, not CLI11's 105-109.
        {{"run", scene, "--no-such-option"}, "The following argument was not expected: --no-such-option"},
        {{"run", scene, "--until", "soon"}, "Could not convert: --until = soon"},
        {{"run", scene, "--interaction", "fastest"}, "--interaction"},
        {{"run", scene, "--cell-order", "hilbert"}, "--cell-order"},
        {{"run", scene, "--set", "run.cell_order=\"z\""}, scene + ": run.cell_order"},
        {{"run"}, "scene is required"},
        {{"frobnicate"}, "A subcommand is required"},
    };
    for (auto c : cases) {
        if (c.args.size() > 1) c.args.insert(c.args.end(), {"--out", out});
        CAPTURE(c.args);
        std::string log;
        const auto start = std::chrono::steady_clock::now();
        const int code = run(c.args, log, 60.0);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        INFO(log);
        CHECK(code == 1);
        CHECK(log.find("clsph: error: " + c.expected) != std::string::npos);
        CHECK(seconds < 30.0);  // a hang guard: each answers in well under a second
        CHECK_FALSE(fs::exists(out));
    }
    // None of them took memory beyond the bounds (an endless /dev/zero read once reached 3 GB).
    rusage usage{};
    getrusage(RUSAGE_CHILDREN, &usage);
    CHECK(usage.ru_maxrss < 1024L * 1024L);  // KiB: under 1 GiB for the largest child
}

TEST_CASE("a blow-up found before the first step: exit 2, named, the state at t = 0 written") {
    const std::string out = work_dir("blow_up_at_start");
    std::string log;
    // A density band the hydrostatic start already leaves.
    const int code = run(args({{"run", scene}, tiny, {"--set", "physics.density_max=1.0000001", "--steps", "5", "--out", out}}), log);
    INFO(log);
    CHECK(code == 2);
    CHECK(log.find("clsph: error: step 1, t = 0 s: particle ") != std::string::npos);
    CHECK(log.find("outside the allowed band") != std::string::npos);
    CHECK(log.find("last good state is in " + out + "/last_good.vtu") != std::string::npos);
    const auto j = read_json(out + "/run.json");
    CHECK(j.at("status") == "failed");
    CHECK(j.at("exit_status") == 2);
    CHECK(j.at("message").get<std::string>().find("outside the allowed band") != std::string::npos);
    CHECK(clsph::read_vtu(out + "/last_good.vtu").size() == tiny_count({"physics.density_max=1.0000001"}).total);
}

TEST_CASE("--help and --version still exit 0") {
    std::string log;
    CHECK(run({"--version"}, log) == 0);
    CHECK(log.find("clsph ") != std::string::npos);
    CHECK(run({"run", "--help"}, log) == 0);
    CHECK(log.find("--steps") != std::string::npos);
}
