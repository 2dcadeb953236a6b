// What the tests of `mpirun ... clsph` share (test_mpi_cli.cpp, test_mpi_failover.cpp): the tiny
// dam break, mpirun's arguments, running a program to its end, and frames compared by id.
#pragma once
#include "process.hpp"

#include <clsph/io.hpp>
#include <nlohmann/json.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace mpi_cli_test {

namespace fs = std::filesystem;
using namespace clsph;

inline const std::string scene = std::string(CLSPH_SOURCE_DIR) + "/scenes/dam_break.json";
// The CLI suite's tiny dam break (6,305 particles).
inline const std::vector<std::string> tiny = {"--set", "physics.dp=0.0146", "--set", "physics.coefsound=10",
                                       "--set", "domain.max=[0.624,0.1898,0.45]", "--set", "fluid[0].max=[0.146,0.1752,0.292]",
                                       "--set", "boundaries.walls[0].max=[0.584,0.1752,0.365]"};

inline std::string work_dir(const std::string& name) {
    const std::string d = std::string(CLSPH_CLI_WORK) + "/" + name;
    fs::remove_all(d);
    fs::create_directories(CLSPH_CLI_WORK);
    return d;
}

// mpiexec -n 2 [flags] clsph ARGS
inline std::vector<std::string> mpi_args(const std::vector<std::string>& clsph_args) {
    std::vector<std::string> a = {CLSPH_MPIEXEC_NUMPROC_FLAG, "2"};
    for (const char* f : CLSPH_MPIEXEC_FLAGS) a.push_back(f);
    a.push_back(CLSPH_CLI);
    a.insert(a.end(), clsph_args.begin(), clsph_args.end());
    return a;
}

inline std::vector<std::string> join(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

inline int run_program(const std::string& program, const std::vector<std::string>& args, std::string& log, double timeout = 120) {
    const std::string path = std::string(CLSPH_CLI_WORK) + "/mpi_command.log";
    int code = 0;
    {
        cli_test::Process p(program, args, path);
        code = p.wait(timeout);
    }
    log = cli_test::read_text(path);
    return code;
}

inline std::map<std::uint32_t, std::array<double, 4>> by_id(const Particles& p, std::size_t& duplicates) {
    std::map<std::uint32_t, std::array<double, 4>> m;
    duplicates = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        duplicates += !m.emplace(p.id[i], std::array<double, 4>{p.position[i][0], p.position[i][1], p.position[i][2],
                                                                 static_cast<double>(p.density[i])})
                           .second;
    return m;
}

// Whether two frames (a .pvtu's pieces or a .vtu) hold the same particles, each once, bit for bit.
inline bool same_frame(const std::string& a_path, const std::string& b_path) {
    std::size_t dup_a = 0, dup_b = 0;
    const auto a = by_id(read_vtu(a_path), dup_a);
    const auto b = by_id(read_vtu(b_path), dup_b);
    std::size_t differ = 0;
    for (const auto& [id, x] : b) {
        const auto it = a.find(id);
        differ += it == a.end() || std::memcmp(it->second.data(), x.data(), sizeof x) != 0;
    }
    MESSAGE(a_path << ": " << a.size() << " particles (" << dup_a << " duplicated), " << b_path << ": " << b.size()
                   << " (" << dup_b << "), " << differ << " missing or differing");
    return dup_a == 0 && dup_b == 0 && a.size() == b.size() && differ == 0;
}

inline nlohmann::json read_json(const std::string& path) {
    std::ifstream f(path);
    return nlohmann::json::parse(f);
}


}  // namespace mpi_cli_test
