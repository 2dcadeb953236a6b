#include "mpi/environment.hpp"

#include "clsph/error.hpp"

#include <cstdlib>
#include <iostream>

namespace clsph::mpi {

std::string error_string(int code) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    if (MPI_Error_string(code, text, &length) != MPI_SUCCESS) return "MPI error " + std::to_string(code);
    int error_class = code;
    MPI_Error_class(code, &error_class);
    return std::string(text, static_cast<std::size_t>(length)) + " (error class " + std::to_string(error_class) + ")";
}

void check(int rc, const char* call, const std::string& what) {
    if (rc == MPI_SUCCESS) return;
    throw Error(std::string(call) + (what.empty() ? "" : " (" + what + ")") + " failed: " + error_string(rc));
}

const char* thread_level_name(int level) {
    switch (level) {
        case MPI_THREAD_SINGLE: return "MPI_THREAD_SINGLE";
        case MPI_THREAD_FUNNELED: return "MPI_THREAD_FUNNELED";
        case MPI_THREAD_SERIALIZED: return "MPI_THREAD_SERIALIZED";
        case MPI_THREAD_MULTIPLE: return "MPI_THREAD_MULTIPLE";
        default: return "an unknown thread level";
    }
}

Environment::Environment(int& argc, char**& argv) { start(&argc, &argv); }
Environment::Environment() { start(nullptr, nullptr); }

void Environment::start(int* argc, char*** argv) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized) throw Error("starting MPI: MPI has already been finalised in this process");
    int initialized = 0;
    MPI_Initialized(&initialized);
    int provided = MPI_THREAD_SINGLE;
    if (initialized) {
        MPI_Query_thread(&provided);
        if (provided < MPI_THREAD_MULTIPLE)
            throw Error(std::string("MPI was initialised with ") + thread_level_name(provided) +
                        "; clsph calls MPI from one host thread per device and needs MPI_THREAD_MULTIPLE"
                        " (initialise it with MPI_Init_thread(..., MPI_THREAD_MULTIPLE, ...))");
    } else {
        // Before MPI_Init the default error handler aborts: a failure here never returns.
        MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided);
        owns_ = true;
        if (provided < MPI_THREAD_MULTIPLE) {
            MPI_Finalize();
            owns_ = false;
            throw Error(std::string("the MPI library provides ") + thread_level_name(provided) +
                        "; clsph calls MPI from one host thread per device and needs MPI_THREAD_MULTIPLE"
                        " (Open MPI: a build with thread support, --enable-mpi-thread-multiple)");
        }
    }
    try {
        check(MPI_Comm_dup(MPI_COMM_WORLD, &world_), "MPI_Comm_dup", "clsph's copy of MPI_COMM_WORLD");
        check(MPI_Comm_set_errhandler(world_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
        check(MPI_Comm_dup(world_, &base_), "MPI_Comm_dup", "clsph's base communicator");
        check(MPI_Comm_split_type(world_, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node_), "MPI_Comm_split_type",
              "the ranks of this node");
        check(MPI_Comm_set_errhandler(node_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
        check(MPI_Comm_rank(world_, &place_.rank), "MPI_Comm_rank");
        check(MPI_Comm_size(world_, &place_.size), "MPI_Comm_size");
        check(MPI_Comm_rank(node_, &place_.local_rank), "MPI_Comm_rank", "on this node");
        check(MPI_Comm_size(node_, &place_.local_size), "MPI_Comm_size", "on this node");
    } catch (...) {
        if (base_ != MPI_COMM_NULL) MPI_Comm_free(&base_);
        if (node_ != MPI_COMM_NULL) MPI_Comm_free(&node_);
        if (world_ != MPI_COMM_NULL) MPI_Comm_free(&world_);
        if (owns_) MPI_Finalize();
        throw;
    }
}

Environment::~Environment() {
    // Freeing a communicator is collective in name only (it does not wait for the other ranks);
    // MPI_Finalize does, which is why a rank that failed calls abort() instead of returning.
    if (base_ != MPI_COMM_NULL) MPI_Comm_free(&base_);
    if (node_ != MPI_COMM_NULL) MPI_Comm_free(&node_);
    if (world_ != MPI_COMM_NULL && !keep_world_) MPI_Comm_free(&world_);
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (owns_ && !finalized) MPI_Finalize();
}

void abort(int code, const std::string& message) {
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (!initialized || finalized) {
        std::cerr << "clsph: " << message << std::endl;
        std::exit(code);
    }
    int rank = 0, size = 1, length = 0;
    char host[MPI_MAX_PROCESSOR_NAME] = {};
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Get_processor_name(host, &length);
    std::cerr << "clsph: rank " << rank << " of " << size << " (" << std::string(host, static_cast<std::size_t>(length))
              << "): " << message << std::endl;
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);  // MPI_Abort does not return; should it, stop this rank at least
}

}  // namespace clsph::mpi
