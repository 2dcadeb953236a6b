#include "run_ranks.hpp"

#include <clsph/ranks.hpp>

#include <sstream>

namespace clsph::app {

bool speaks(const RunArgs& args) { return !args.ranks || rank_of(*args.ranks) == 0; }

std::vector<std::string> all_device_names(const Simulation& sim, const RunArgs& args) {
    const auto mine = sim.device_names();
    if (!args.ranks) return mine;
    std::string joined;
    for (const auto& n : mine) joined += n + '\n';
    std::vector<std::string> out;
    const auto all = gather_text(*args.ranks, joined);
    for (std::size_t r = 0; r < all.size(); ++r) {
        std::istringstream lines(all[r]);
        for (std::string line; std::getline(lines, line);) out.push_back("rank " + std::to_string(r) + ": " + line);
    }
    return out;
}

}  // namespace clsph::app
