#include "multi/ranks.hpp"

#include "clsph/error.hpp"
#include "clsph/ranks.hpp"

#include <cstdlib>
#include <iostream>

namespace clsph {

int rank_of(const Ranks& ranks) { return ranks.rank(); }
int ranks_in(const Ranks& ranks) { return ranks.size(); }
void abort_all(const Ranks& ranks, int code, const std::string& message) { ranks.abort(code, message); }

#if !CLSPH_HAVE_MPI
std::shared_ptr<Ranks> mpi_ranks(int&, char**&) {
    throw Error("this clsph was built without MPI (CMake found no MPI, or -DCLSPH_MPI=OFF): it runs in one process; "
                "install libopenmpi-dev and openmpi-bin and build again to run across ranks");
}
#endif

}  // namespace clsph
