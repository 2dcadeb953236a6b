#include "clsph/version.hpp"
namespace clsph {
const char* version() { return CLSPH_VERSION_STRING; }
}  // namespace clsph
