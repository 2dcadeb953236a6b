// The clsph command-line tool. It uses only the public API (host/include/clsph).
#include <CLI/CLI.hpp>
#include <clsph/devices.hpp>
#include <clsph/error.hpp>
#include <clsph/version.hpp>

#include <iostream>

int main(int argc, char** argv) {
    CLI::App app{"clsph: multi-device SPH fluid simulation on OpenCL"};
    app.set_version_flag("--version", std::string("clsph ") + clsph::version());
    app.require_subcommand(1);

    auto* devices = app.add_subcommand("devices", "list the OpenCL devices clsph can use, in selection order");
    std::string spec;
    devices->add_option("--devices", spec, "show which devices a selection spec picks (all|gpu|cpu|0,2|platform:NAME)");

    CLI11_PARSE(app, argc, argv);
    try {
        if (*devices) {
            const auto all = clsph::list_devices();
            std::cout << clsph::format_device_table(all);
            const std::string used = spec.empty() ? clsph::default_device_spec() : spec;
            const auto chosen = clsph::select_devices(all, used);
            std::cout << "selection '" << used << "' picks:";
            for (auto i : chosen) std::cout << ' ' << i;
            std::cout << '\n';
        }
    } catch (const clsph::Error& e) {
        std::cerr << "clsph: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
