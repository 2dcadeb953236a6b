// The .cl sources: embedded into the library at build time (cmake/embed_kernels.cmake), or read
// from $CLSPH_KERNEL_DIR when set, so kernels can be edited without rebuilding while developing.
#pragma once
#include <string>

namespace clsph::cl_rt {

// The full text of kernels/<file>, with `#include "x.h"` lines replaced by the text of kernels/x.h
// (drivers differ in how they resolve includes, so we resolve them ourselves).
// Throws clsph::Error naming the file when it does not exist.
std::string kernel_source(const std::string& file);

}  // namespace clsph::cl_rt
