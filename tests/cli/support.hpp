// What the CLI tests share: the tiny dam break, running the tool, reading its files back.
#pragma once
#include "process.hpp"

#include <clsph/io.hpp>
#include <clsph/scene_io.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cli_test {

namespace fs = std::filesystem;

inline const std::string source = CLSPH_SOURCE_DIR;
inline const std::string scene = source + "/scenes/dam_break.json";

// scenes/dam_break.json at dp = 2 x 0.0073 (the periodic slice widened to 13 particles, three
// kernel supports) and half the sound speed: seconds on a 2-core CPU.
inline const std::vector<std::string> tiny = {
    "--set", "physics.dp=0.0146", "--set", "physics.coefsound=10",
    "--set", "domain.max=[0.624,0.1898,0.45]", "--set", "fluid[0].max=[0.146,0.1752,0.292]",
    "--set", "boundaries.walls[0].max=[0.584,0.1752,0.365]"};

// The tiny dam break's particles as the library builds them (clsph::load_scene with the same
// --set overrides, then Scene::build_particles), so the tests compare what the tool wrote against
// the scene rather than against a number copied from an earlier run. `more` are further --set
// KEY=VALUE overrides the run was given.
struct TinyCount {
    std::size_t total = 0, fluid = 0, boundary = 0;
};
inline TinyCount tiny_count(const std::vector<std::string>& more = {}) {
    std::vector<std::string> overrides;
    for (std::size_t i = 0; i + 1 < tiny.size(); i += 2) overrides.push_back(tiny[i + 1]);  // {"--set", KEY=VALUE}...
    overrides.insert(overrides.end(), more.begin(), more.end());
    const clsph::Particles p = clsph::load_scene(scene, overrides).build_particles();
    TinyCount c;
    c.total = p.size();
    c.fluid = static_cast<std::size_t>(std::count(p.type.begin(), p.type.end(), clsph::ParticleType::fluid));
    c.boundary = c.total - c.fluid;
    return c;
}

// How many frames a run from t = 0 to `until` with a frame every `every` writes: one at t = 0 and
// one at each multiple of `every` up to `until` (docs/cli.md: frames land exactly on multiples of DT).
inline std::size_t frames_implied(double until, double every) {
    return static_cast<std::size_t>(std::floor(until / every + 1e-9)) + 1;
}

inline std::string work_dir(const std::string& name) {
    const std::string dir = std::string(CLSPH_CLI_WORK) + "/" + name;
    fs::remove_all(dir);
    fs::create_directories(CLSPH_CLI_WORK);
    return dir;
}

// How many devices a selection picks (`clsph devices --devices SPEC`).
inline std::size_t devices_picked(const std::string& spec) {
    std::string log;
    run({"devices", "--devices", spec}, log);
    const auto at = log.find("picks:");
    if (at == std::string::npos) return 0;
    std::istringstream in(log.substr(at + 6));
    std::size_t n = 0;
    for (std::string index; in >> index;) ++n;
    return n;
}

inline std::vector<std::string> args(std::initializer_list<std::vector<std::string>> parts) {
    std::vector<std::string> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
}

inline std::vector<std::vector<std::string>> read_csv_rows(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

inline std::size_t count_files(const std::string& dir, const std::string& prefix, const std::string& extension) {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        n += name.rfind(prefix, 0) == 0 && e.path().extension() == extension;
    }
    return n;
}

inline bool near(double a, double b) { return std::abs(a - b) <= 1e-8 * std::max(1.0, std::abs(b)); }

// The ids of a frame in id order, with their positions: VTU and CSV must agree particle by particle.
inline std::vector<std::pair<std::uint32_t, std::array<double, 3>>> by_id(const clsph::Particles& p) {
    std::vector<std::pair<std::uint32_t, std::array<double, 3>>> out;
    for (std::size_t i = 0; i < p.size(); ++i) out.emplace_back(p.id[i], p.position[i]);
    std::sort(out.begin(), out.end());
    return out;
}

inline nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(cli_test::read_text(path)); }

}  // namespace cli_test
