#include "multi/ranks.hpp"

#include "clsph/error.hpp"
#include "clsph/ranks.hpp"

#include <cstdlib>
#include <iostream>

namespace clsph {

int rank_of(const Ranks& ranks) { return ranks.rank(); }
int ranks_in(const Ranks& ranks) { return ranks.size(); }
void wait_for_all(Ranks& ranks) {
    std::vector<std::uint64_t> none{0};
    ranks.sum(none);
}
bool any_rank(Ranks& ranks, bool mine) {
    std::vector<std::uint64_t> n{mine ? 1u : 0u};
    ranks.sum(n);
    return n[0] > 0;
}
std::vector<std::string> gather_text(Ranks& ranks, const std::string& mine) { return ranks.gather_text(mine); }
std::vector<std::string> gather_text_to(Ranks& ranks, const std::string& mine, int root) {
    return ranks.gather_text_to(mine, root);
}
void give_up(Ranks& ranks, const std::string& why) { ranks.give_up(why); }
void recover(Ranks& ranks) { ranks.recover(); }
void abort_all(const Ranks& ranks, int code, const std::string& message) {
    ranks.abort(code, message);
    std::abort();  // not reached (Ranks::abort does not return); says so to the compiler, which cannot see through the virtual call
}

#if !CLSPH_HAVE_MPI
std::shared_ptr<Ranks> mpi_ranks(int&, char**&) {
    throw Error("this clsph was built without MPI (CMake found no MPI, or -DCLSPH_MPI=OFF): it runs in one process; "
                "install libopenmpi-dev and openmpi-bin and build again to run across ranks");
}
#endif

}  // namespace clsph
