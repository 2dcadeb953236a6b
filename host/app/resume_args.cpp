#include "resume_args.hpp"

#include "run_options.hpp"

#include <CLI/CLI.hpp>
#include <clsph/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

namespace clsph::app {

RunArgs resume_args(const std::string& dir, const std::optional<double>& until, const std::string& devices,
                    const std::optional<std::string>& steps, const std::vector<std::string>& own_argv) {
    std::ifstream f(dir + "/run.json");
    if (!f) throw Error("clsph resume: no run.json in " + dir + " (not the output directory of a clsph run)");
    std::vector<std::string> original;
    try {
        original = nlohmann::json::parse(f).at("command_line").get<std::vector<std::string>>();
    } catch (const std::exception& e) {
        throw Error("clsph resume: cannot read the command line from " + dir + "/run.json: " + e.what());
    }
    const auto run_at = std::find(original.begin(), original.end(), "run");
    if (run_at == original.end()) throw Error("clsph resume: " + dir + "/run.json records no `clsph run` command line");
    // Dropped with their values: what the resume sets itself, and what only a fresh start means.
    std::vector<std::string> with_value = {"--out"};
    if (until) with_value.push_back("--until");
    if (!devices.empty()) with_value.push_back("--devices");
    if (steps) with_value.push_back("--steps");
    const std::vector<std::string> flags = {"--force", "--dry-run"};
    std::vector<std::string> argv;
    for (auto it = run_at + 1; it != original.end(); ++it) {
        const std::string& a = *it;
        const std::string name = a.substr(0, a.find('='));
        if (std::find(flags.begin(), flags.end(), a) != flags.end()) continue;
        if (std::find(with_value.begin(), with_value.end(), name) != with_value.end()) {
            if (a.find('=') == std::string::npos && it + 1 != original.end()) ++it;
            continue;
        }
        argv.push_back(a);
    }
    if (until) argv.insert(argv.end(), {"--until", std::to_string(*until)});
    if (!devices.empty()) argv.insert(argv.end(), {"--devices", devices});
    if (steps) argv.insert(argv.end(), {"--steps", *steps});
    argv.insert(argv.end(), {"--out", dir});
    CLI::App app{"clsph resume"};
    auto* run = app.add_subcommand("run");
    RunOptions options(*run);  // not const: parsing writes into it
    std::vector<std::string> reversed{"run"};
    reversed.insert(reversed.end(), argv.begin(), argv.end());
    std::reverse(reversed.begin(), reversed.end());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw Error(std::string("clsph resume: the recorded command line does not parse: ") + e.what());
    }
    RunArgs a = options.args();
    a.command_line.assign(original.begin(), original.end());
    a.resume_dir = dir;
    a.resume_command_line = own_argv;
    return a;
}

}  // namespace clsph::app
