// MPI for one run across ranks (issue 21): its start and end, where this rank stands, and errors.
// Compiled only when clsph is built with MPI (CLSPH_MPI).
//
// The engine calls MPI from one host thread per device, so it needs MPI_THREAD_MULTIPLE: the
// Environment asks for it and refuses less. Its communicators return errors instead of aborting
// (MPI_ERRORS_RETURN), and check() turns them into clsph::Error naming the MPI call and
// MPI_Error_string. An error that one rank cannot recover from must stop every rank, or the
// others wait for its messages forever: a program catches clsph::Error around its run and calls
// abort(), which prints the message with the rank and calls MPI_Abort.
#pragma once
#include "multi/rank_devices.hpp"

#include <mpi.h>

#include <string>

namespace clsph::mpi {

// MPI_Error_string of an MPI error code ("MPI_ERR_RANK: invalid rank").
std::string error_string(int code);
// Throws clsph::Error "MPI_Isend (`what`) failed: MPI_ERR_RANK: invalid rank" unless rc is MPI_SUCCESS.
void check(int rc, const char* call, const std::string& what = {});
// "MPI_THREAD_MULTIPLE", ...
const char* thread_level_name(int level);

class Environment {
public:
    // Initialises MPI (MPI_Init_thread, asking for MPI_THREAD_MULTIPLE) unless the host program
    // already did, and finalises it when destroyed if it initialised it. Throws clsph::Error when
    // the library provides (or the host program asked for) less than MPI_THREAD_MULTIPLE.
    Environment(int& argc, char**& argv);
    Environment();
    ~Environment();
    Environment(const Environment&) = delete;
    Environment& operator=(const Environment&) = delete;

    int rank() const { return place_.rank; }
    int size() const { return place_.size; }
    // Among the ranks that share this rank's node (MPI_COMM_TYPE_SHARED): what deals its devices.
    int local_rank() const { return place_.local_rank; }
    int local_size() const { return place_.local_size; }
    const multi::RankPlace& place() const { return place_; }
    // clsph's own copy of MPI_COMM_WORLD (its messages never meet the host program's), and the
    // ranks of this node; both return errors (MPI_ERRORS_RETURN).
    MPI_Comm comm() const { return world_; }
    MPI_Comm node() const { return node_; }
    // Another copy of MPI_COMM_WORLD that nothing talks on: only duplicated, by every rank in
    // the same order, for communicators that must start clean (Ranks::recover after a failure,
    // when the others may hold a given-up step's collectives).
    MPI_Comm base() const { return base_; }
    // comm() is not freed at the end: a given-up step may have left collectives on it (mpi/alarm.hpp).
    void keep_comm() { keep_world_ = true; }
    // Whether this Environment initialised MPI (and so finalises it).
    bool owns_mpi() const { return owns_; }

private:
    void start(int* argc, char*** argv);
    bool owns_ = false, keep_world_ = false;
    MPI_Comm world_ = MPI_COMM_NULL, node_ = MPI_COMM_NULL, base_ = MPI_COMM_NULL;
    multi::RankPlace place_;
};

// Prints "clsph: rank R of N (host): message" to stderr and stops every rank (MPI_Abort with
// `code` on MPI_COMM_WORLD). Without MPI initialised, prints and exits with `code`.
[[noreturn]] void abort(int code, const std::string& message);

}  // namespace clsph::mpi
