// The smallest host program: link clsph, list the OpenCL devices it would use.
#include <clsph/devices.hpp>
#include <clsph/error.hpp>
#include <clsph/version.hpp>

#include <iostream>

int main() {
    try {
        const auto devices = clsph::list_devices();
        std::cout << "clsph " << clsph::version() << " sees " << devices.size() << " device(s):\n"
                  << clsph::format_device_table(devices);
    } catch (const clsph::Error& e) {
        std::cerr << "error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
