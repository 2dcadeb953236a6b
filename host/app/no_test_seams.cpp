// The shipped clsph: no test seams (test_seams.hpp).
#include "test_seams.hpp"

namespace clsph::app {

void add_test_seams(Options&) {}

}  // namespace clsph::app
