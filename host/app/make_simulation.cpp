#include "make_simulation.hpp"

#include "test_seams.hpp"

#include <clsph/checkpoint.hpp>
#include <clsph/error.hpp>

#include <chrono>
#include <iomanip>
#include <iostream>

namespace clsph::app {

std::unique_ptr<Simulation> make_simulation(const Scene& scene, const RunArgs& args, const Checkpoint* checkpoint) {
    Options opts;
    opts.devices = args.devices;
    opts.profile = args.profile;
    opts.synchronous = args.synchronous;
    if (args.steps) opts.step_limit = *args.steps + (checkpoint ? checkpoint->step : 0);  // the step ahead stops exactly there
    if (!args.interaction.empty()) opts.interaction = interaction_from_name(args.interaction);
    if (!args.cell_order.empty()) opts.cell_order = cell_order_from_name(args.cell_order);
    opts.balance = balance_mode_from_name(args.balance);
    opts.balance_log = args.balance_log;
    opts.ranks = args.ranks;
    // A long set-up (hundreds of millions of particles) says what it is doing, once it has taken
    // more than two seconds; a short one stays quiet.
    opts.on_setup = [start = std::chrono::steady_clock::now()](const std::string& line) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (s > 2.0) std::cout << "  set-up, " << std::fixed << std::setprecision(1) << s << std::defaultfloat << " s: " << line << std::endl;
    };
    if (args.test_seams) add_test_seams(opts);  // only clsph-faulty has any (test_seams.hpp)
    return with_scene_path(args, [&] {
        return checkpoint ? std::make_unique<Simulation>(scene, *checkpoint, opts) : std::make_unique<Simulation>(scene, opts);
    });
}

}  // namespace clsph::app
