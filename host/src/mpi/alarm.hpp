// How the ranks of one run learn that one of them gave up a step (a device of its failed), so
// that none waits for it forever: each rank keeps a receive posted for a notice from any rank, on a
// communicator of the alarm's own; a rank that gives up sends the notice (its error's text) to
// every other rank, and from then on every wait of the run (the collectives, the links: messages.hpp)
// on every rank looks at the alarm between its looks at MPI and throws clsph::RankFailure once it
// has gone off. What the given-up step left in flight is let go; Ranks::recover() then starts the
// ranks over on fresh communicators, with a fresh alarm.
#pragma once
#include <mpi.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace clsph::mpi {

class Alarm {
public:
    // A duplicate of `base` for the notices (collective over `base`), the receive posted.
    explicit Alarm(MPI_Comm base);
    // Cancels the receive if nothing came; lets go of the notices sent (they are small and gone).
    ~Alarm();
    Alarm(const Alarm&) = delete;
    Alarm& operator=(const Alarm&) = delete;

    // This rank gives up: the notice (`why`, cut to a few KiB) to every other rank, once, and the
    // alarm gone off here too (the waits of this rank's other threads throw as well).
    void raise(const std::string& why);
    // Throws RankFailure if the alarm has gone off, here or by another rank's notice (thread-safe).
    void check();
    bool gone_off() const { return off_.load(); }

private:
    static constexpr int kNotice = 4096;
    [[noreturn]] void fail();
    MPI_Comm comm_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
    std::mutex mutex_;  // one thread at a time tests the request
    MPI_Request incoming_ = MPI_REQUEST_NULL;
    std::vector<char> notice_ = std::vector<char>(kNotice, '\0');
    std::unique_ptr<std::string> outgoing_ = std::make_unique<std::string>();  // let go with the notices
    std::vector<MPI_Request> sent_;
    std::atomic<bool> off_{false};
    int from_ = -1;       // the rank whose notice set it off (this rank's own when it raised it)
    std::string why_;
};

}  // namespace clsph::mpi
