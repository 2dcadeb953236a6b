#include "mpi/alarm.hpp"

#include "clsph/error.hpp"
#include "mpi/environment.hpp"

#include <algorithm>
#include <cstring>

namespace clsph::mpi {

Alarm::Alarm(MPI_Comm base) {
    mpi::check(MPI_Comm_dup(base, &comm_), "MPI_Comm_dup", "a communicator for the ranks' failure notices");
    mpi::check(MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    mpi::check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    mpi::check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
    mpi::check(MPI_Irecv(notice_.data(), kNotice, MPI_CHAR, MPI_ANY_SOURCE, 0, comm_, &incoming_), "MPI_Irecv",
          "the ranks' failure notices");
}

Alarm::~Alarm() {
    if (incoming_ != MPI_REQUEST_NULL) {
        MPI_Cancel(&incoming_);  // a receive: cancelled at once if nothing matched it
        MPI_Wait(&incoming_, MPI_STATUS_IGNORE);
    }
    // The notices are a few KiB (sent eagerly); a peer that never takes them must not hold us, and
    // their communicator stays (never freed under messages in flight).
    for (MPI_Request& r : sent_)
        if (r != MPI_REQUEST_NULL) MPI_Request_free(&r);
    if (sent_.empty()) MPI_Comm_free(&comm_);
    else static_cast<void>(outgoing_.release());
}

void Alarm::raise(const std::string& why) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (off_.load()) return;  // once: a notice came, or this rank raised it already
    from_ = rank_;
    why_ = why;
    *outgoing_ = why.substr(0, static_cast<std::size_t>(kNotice - 1));
    for (int r = 0; r < size_; ++r) {
        if (r == rank_) continue;
        MPI_Request q = MPI_REQUEST_NULL;
        // No check(): a rank giving up says what it can; its own error is the one to report.
        if (MPI_Isend(outgoing_->data(), static_cast<int>(outgoing_->size()) + 1, MPI_CHAR, r, 0, comm_, &q) == MPI_SUCCESS)
            sent_.push_back(q);
    }
    off_.store(true);
}

void Alarm::check() {
    if (off_.load()) fail();
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || incoming_ == MPI_REQUEST_NULL) return;  // another thread is looking
    int came = 0;
    MPI_Status status;
    if (MPI_Test(&incoming_, &came, &status) != MPI_SUCCESS || !came) return;
    from_ = status.MPI_SOURCE;
    notice_.back() = '\0';
    why_ = notice_.data();
    off_.store(true);
    lock.unlock();
    fail();
}

void Alarm::fail() {
    std::lock_guard<std::mutex> lock(mutex_);
    throw RankFailure(from_, "rank " + std::to_string(from_) + " of " + std::to_string(size_) + ": " + why_);
}

}  // namespace clsph::mpi
