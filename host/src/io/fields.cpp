// FrameFields: which point-data arrays a frame holds (clsph run --fields).
#include "clsph/error.hpp"
#include "clsph/io.hpp"

#include <sstream>

namespace clsph {

FrameFields FrameFields::parse(const std::string& list, const std::string& option) {
    if (list == "all") return FrameFields{};
    FrameFields f;
    f.id = f.type = f.velocity = f.density = f.pressure = false;
    std::istringstream in(list);
    std::string name;
    bool any = false;
    while (std::getline(in, name, ',')) {
        if (name == "id") f.id = true;
        else if (name == "type") f.type = true;
        else if (name == "velocity") f.velocity = true;
        else if (name == "density") f.density = true;
        else if (name == "pressure") f.pressure = true;
        else if (name == "position") {}  // always written
        else
            throw Error(option + ": unknown field \"" + name +
                        "\" (expected \"all\" or a comma-separated list of id, type, velocity, density, pressure; "
                        "positions are always written)");
        any = true;
    }
    if (!any) throw Error(option + ": expected \"all\" or a comma-separated list of id, type, velocity, density, pressure");
    return f;
}

}  // namespace clsph
