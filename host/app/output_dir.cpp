#include "output_dir.hpp"

#include <clsph/error.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <vector>

namespace clsph::app {
namespace fs = std::filesystem;
namespace {

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }
bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The names a run (and scripts/run.sh's plot) writes; --force removes these and nothing else, so
// a mistyped --out pointing at a user's directory costs them no files of their own.
bool written_by_a_run(const std::string& name) {
    if (ends_with(name, ".tmp")) return true;  // a writer cut short mid-rename
    if (starts_with(name, "frame_") && (ends_with(name, ".vtu") || ends_with(name, ".pvtu") || ends_with(name, ".csv"))) return true;
    if ((starts_with(name, "probe_") || starts_with(name, "body_")) && ends_with(name, ".csv")) return true;
    if (starts_with(name, "checkpoint_") && ends_with(name, ".clsph")) return true;
    if (starts_with(name, "surge_front.")) return true;
    if (starts_with(name, "surface_") && (ends_with(name, ".vtp") || ends_with(name, ".ply"))) return true;
    if ((starts_with(name, "render_") && ends_with(name, ".png")) || name == "render.mp4") return true;
    if (name == "last_good.vtu" || name == "last_good.csv") return true;  // a failed run's state: not this run's
    return ends_with(name, ".pvd") || name == "stats.csv" || name == "run.json";
}

[[noreturn]] void fail(const std::string& what, const std::error_code& ec) {
    throw Error(what + (ec ? ": " + ec.message() : std::string()));
}

}  // namespace

void check_output_dir(const std::string& dir, bool force) {
    std::error_code ec;
    const auto status = fs::status(dir, ec);
    if (!fs::exists(status)) return;
    if (!fs::is_directory(status)) fail("output path '" + dir + "' exists and is not a directory", {});
    if (force) return;
    if (!fs::is_empty(dir, ec))
        fail("output directory '" + dir + "' already exists and is not empty; pass --force to overwrite its run files, "
             "or choose another with --out", {});
}

void prepare_output_dir(const std::string& dir, bool force) {
    check_output_dir(dir, force);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) fail("cannot create output directory '" + dir + "'", ec);
    if (!force) return;
    // Collected first: removing entries while iterating a directory is unspecified.
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(dir, ec))
        if (entry.is_regular_file() && written_by_a_run(entry.path().filename().string())) stale.push_back(entry.path());
    if (ec) fail("cannot list output directory '" + dir + "'", ec);
    for (const auto& path : stale)
        if (!fs::remove(path, ec) && ec) fail("cannot remove '" + path.string() + "'", ec);
}

std::vector<std::pair<std::uint64_t, std::string>> list_checkpoints(const std::string& dir) {
    std::vector<std::pair<std::uint64_t, std::string>> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        if (!starts_with(name, "checkpoint_") || !ends_with(name, ".clsph")) continue;
        const std::string digits = name.substr(11, name.size() - 11 - 6);
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        out.emplace_back(std::stoull(digits), e.path().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string checkpoint_path(const std::string& dir, std::uint64_t step) {
    char name[64];
    std::snprintf(name, sizeof name, "checkpoint_%05llu.clsph", static_cast<unsigned long long>(step));
    return dir + "/" + name;
}

void remove_old_checkpoints(const std::string& dir, std::size_t keep) {
    const auto all = list_checkpoints(dir);
    for (std::size_t i = 0; i + keep < all.size(); ++i) std::remove(all[i].second.c_str());
}

}  // namespace clsph::app
