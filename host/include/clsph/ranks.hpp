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

// Going on after a rank's device failed (clsph run --on-device-failure continue across ranks).
// A rank that cannot finish a step calls give_up with its error: every other rank's wait in that
// step (a collective, a link to a slab of another rank) then throws RankFailure (clsph/error.hpp)
// instead of waiting for it. The engine gives up by itself when a device fails inside a step; a
// program gives up for failures of its own between steps (a frame's download, say). Then every
// rank calls recover, once, in step with the others: the ranks go on over fresh communicators
// (what the given-up step left in flight meets nothing of what follows); the Simulations made
// before must not step again, and a new one (from a checkpoint, on the devices left) takes over.
void give_up(Ranks& ranks, const std::string& why);
void recover(Ranks& ranks);

// Stops every rank after an error on this one (MPI_Abort), printing `message` with the rank, so
// the others do not wait for its messages forever. Without MPI: prints and exits with `code`.
[[noreturn]] void abort_all(const Ranks& ranks, int code, const std::string& message);

}  // namespace clsph
