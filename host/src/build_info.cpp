#include "clsph/build_info.hpp"

#if CLSPH_HAVE_MPI
#include <mpi.h>
#endif

namespace clsph {

#if CLSPH_HAVE_MPI
bool built_with_mpi() { return true; }

std::string mpi_library_version() {
    char text[MPI_MAX_LIBRARY_VERSION_STRING] = {};
    int length = 0;
    if (MPI_Get_library_version(text, &length) != MPI_SUCCESS) return "MPI (version unknown)";
    std::string s(text, static_cast<std::size_t>(length));
    s = s.substr(0, s.find('\n'));
    while (!s.empty() && (s.back() == '\0' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
    return s;
}
#else
bool built_with_mpi() { return false; }
std::string mpi_library_version() { return {}; }
#endif

}  // namespace clsph
