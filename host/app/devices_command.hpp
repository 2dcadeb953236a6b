// clsph devices [--devices SPEC]: the OpenCL devices clsph can use, in selection order, and which
// of them a selection spec picks.
#pragma once
#include <string>

namespace clsph::app {

int devices_command(const std::string& spec);

}  // namespace clsph::app
