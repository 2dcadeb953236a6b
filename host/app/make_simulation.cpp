#include "make_simulation.hpp"

#include <clsph/error.hpp>
#include <clsph/testing.hpp>

#include <cstdlib>
#include <sstream>

namespace clsph::app {

std::unique_ptr<Simulation> make_simulation(const Scene& scene, const RunArgs& args) {
    Options opts;
    opts.devices = args.devices;
    opts.profile = args.profile;
    opts.synchronous = args.synchronous;
    if (args.steps) opts.step_limit = *args.steps;  // the step ahead stops exactly there
    if (!args.interaction.empty()) opts.interaction = interaction_from_name(args.interaction);
    opts.balance = balance_mode_from_name(args.balance);
    opts.balance_log = args.balance_log;
    // Test hook (tests/cli): CLSPH_TEST_DEVICE_FAILURE=STEP[:DEVICE] simulates a device failing
    // when that step starts, to exercise the mid-run error path end to end.
    if (const char* v = std::getenv("CLSPH_TEST_DEVICE_FAILURE")) {
        const std::string text = v;
        std::size_t step = 0, device = 0;
        char colon = 0;
        std::istringstream in(text);
        if (!(in >> step) || step == 0 || (in >> colon && (colon != ':' || !(in >> device))) || !in.eof())
            throw Error("CLSPH_TEST_DEVICE_FAILURE: expected STEP or STEP:DEVICE (STEP >= 1), got '" + text + "'");
        testing::Seams seams;
        seams.fail_at_step = step;
        seams.fail_device = device;
        testing::set_seams(opts, std::move(seams));
    }
    try {
        return std::make_unique<Simulation>(scene, opts);
    } catch (const SceneError& e) {
        const std::string message = e.what();
        if (message.compare(0, args.scene_path.size() + 1, args.scene_path + ":") == 0) throw;
        throw SceneError(args.scene_path + ": " + message);
    }
}

}  // namespace clsph::app
