// How this clsph was built (what `clsph --version` reports beside the version).
#pragma once
#include <string>

namespace clsph {

// Whether the library was built with MPI (CMake option CLSPH_MPI, on where MPI is found), so a
// run can span MPI ranks (issue 21).
bool built_with_mpi();

// The MPI library's own description (MPI_Get_library_version's first line, e.g. "Open MPI
// v4.1.4, package: Debian OpenMPI, ...") when built with MPI, else empty. Needs no MPI_Init.
std::string mpi_library_version();

}  // namespace clsph
