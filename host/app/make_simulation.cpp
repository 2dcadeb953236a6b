#include "make_simulation.hpp"

#include <clsph/error.hpp>

namespace clsph::app {

std::unique_ptr<Simulation> make_simulation(const Scene& scene, const RunArgs& args) {
    Options opts;
    opts.devices = args.devices;
    opts.profile = args.profile;
    opts.coarse = args.coarse;
    opts.balance = args.balance;
    opts.balance_log = args.balance_log;
    try {
        return std::make_unique<Simulation>(scene, opts);
    } catch (const SceneError& e) {
        const std::string message = e.what();
        if (message.compare(0, args.scene_path.size() + 1, args.scene_path + ":") == 0) throw;
        throw SceneError(args.scene_path + ": " + message);
    }
}

}  // namespace clsph::app
