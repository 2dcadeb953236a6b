// The processes one simulation spans (issue 21: `mpirun -np N clsph run ...`). A host program that
// runs one simulation over MPI ranks makes a Ranks once, before any Simulation, and gives it to
// each rank's Simulation through Options::ranks: every rank then drives its own devices and owns
// a consecutive run of the chain of slabs, and the step's collectives (the exchange between
// neighbouring slabs, the balancer's times and cuts, the reductions) go between the ranks. No MPI
// types here: a program includes this header whether or not clsph was built with MPI
// (clsph/build_info.hpp says).
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace clsph {

class Ranks;  // opaque; shared by the Simulations of one process

// This process's place among the ranks of MPI_COMM_WORLD, initialising MPI (asking for
// MPI_THREAD_MULTIPLE) unless the host program did; MPI is finalised when the last reference goes
// if it was initialised here. Throws clsph::Error in a build without MPI, or when the MPI library
// cannot give MPI_THREAD_MULTIPLE.
std::shared_ptr<Ranks> mpi_ranks(int& argc, char**& argv);

int rank_of(const Ranks& ranks);   // 0 .. ranks_in(ranks) - 1
int ranks_in(const Ranks& ranks);  // how many processes the run spans

// Collectives a host program needs around a run (every rank must call them, in the same order).
void wait_for_all(Ranks& ranks);                                           // a barrier
bool any_rank(Ranks& ranks, bool mine);                                    // true if any rank says so
std::vector<std::string> gather_text(Ranks& ranks, const std::string& mine);  // every rank's, in rank order
// Every rank's, in rank order, on rank `root` only (empty on the others): what one rank writes.
std::vector<std::string> gather_text_to(Ranks& ranks, const std::string& mine, int root);

// Stops every rank after an error on this one (MPI_Abort), printing `message` with the rank, so
// the others do not wait for its messages forever. Without MPI: prints and exits with `code`.
[[noreturn]] void abort_all(const Ranks& ranks, int code, const std::string& message);

}  // namespace clsph
