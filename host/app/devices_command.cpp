#include "devices_command.hpp"

#include <clsph/devices.hpp>

#include <iostream>

namespace clsph::app {

int devices_command(const std::string& spec) {
    const auto all = list_devices();
    std::cout << format_device_table(all);
    const std::string used = spec.empty() ? default_device_spec() : spec;
    const auto chosen = select_devices(all, used);
    std::cout << "selection '" << used << "' picks:";
    for (auto i : chosen) std::cout << ' ' << i;
    std::cout << '\n';
    return 0;
}

}  // namespace clsph::app
