#include "mpi/link.hpp"

#include "cl/errors.hpp"
#include "clsph/error.hpp"
#include "mpi/environment.hpp"

#include <exception>
#include <limits>

namespace clsph::multi {
namespace {

using device::ParticleArrays;

int count_tag(const MpiChannel& c) { return 2 * c.link; }
int payload_tag(const MpiChannel& c) { return 2 * c.link + 1; }

void check_channel(const MpiChannel& c, const char* half) {
    const std::string what = std::string("an MPI ") + half + " link";
    if (c.comm == MPI_COMM_NULL) throw Error(what + ": no communicator");
    int size = 0;
    mpi::check(MPI_Comm_size(c.comm, &size), "MPI_Comm_size", what);
    if (c.peer < 0 || c.peer >= size)
        throw Error(what + ": rank " + std::to_string(c.peer) + " is not one of the " + std::to_string(size) + " ranks");
    const int limit = mpi::tag_limit(c.comm);
    if (c.link < 0 || c.link > (limit - 1) / 2)
        throw Error(what + ": link " + std::to_string(c.link) + " is not in 0.." + std::to_string((limit - 1) / 2) +
                    " (its tags, 2 link and 2 link + 1, must be at most MPI_TAG_UB = " + std::to_string(limit) + ")");
    mpi::chunks(0, c.chunk_bytes);  // throws for a chunk MPI cannot send
}

// When an exception unwinds through a link, the run is about to abort: messages in flight are let
// go rather than waited for (their peer may never answer), and the staging they may still touch
// is left allocated.
void let_go(std::vector<MPI_Request>& requests, std::unique_ptr<cl_rt::PinnedHost>& staging, bool cancel) {
    for (MPI_Request& r : requests) {
        if (r == MPI_REQUEST_NULL) continue;
        if (cancel) MPI_Cancel(&r);
        MPI_Request_free(&r);
    }
    if (!requests.empty()) static_cast<void>(staging.release());
    requests.clear();
}

}  // namespace

// ---- the sender's half ----

MpiSendLink::MpiSendLink(cl_rt::Device& from, const MpiChannel& channel)
    : from_(from), channel_(channel), staging_(std::make_unique<cl_rt::PinnedHost>()) {
    check_channel(channel_, "send");
}

MpiSendLink::~MpiSendLink() {
    if (std::uncaught_exceptions() == 0) {
        try {
            wait();
            return;
        } catch (const std::exception&) {
        }
    }
    if (!posted_) static_cast<void>(staging_.release());  // the device may still be reading into it
    let_go(requests_, staging_, false);
}

std::string MpiSendLink::what() const {
    return "sending " + std::to_string(n_) + " particles to rank " + std::to_string(channel_.peer) + " over link " +
           std::to_string(channel_.link);
}

void MpiSendLink::send(const ParticleArrays& src, std::size_t first, std::size_t n) {
    wait();
    const std::size_t capacity = src.capacity();
    if (first > capacity || n > capacity - first)
        throw Error("sending particles [" + std::to_string(first) + ", " + std::to_string(first) + " + " +
                    std::to_string(n) + ") to rank " + std::to_string(channel_.peer) + " over link " +
                    std::to_string(channel_.link) + ": the arrays hold " + std::to_string(capacity));
    n_ = n;
    count_message_ = n;
    MPI_Request r = MPI_REQUEST_NULL;
    mpi::check(MPI_Isend(&count_message_, 1, MPI_UINT64_T, channel_.peer, count_tag(channel_), channel_.comm, &r),
               "MPI_Isend", what() + ": the count");
    requests_.push_back(r);
    posted_ = false;
    if (n == 0) return;
    staging_->reserve(from_, n * ParticleArrays::kBytesPerParticle);
    device::read_particles(from_, src, first, n, staging_->data(), read_, cl_rt::Device::On::transfer);
    cl_rt::check(from_.transfer_queue().flush(), what() + " (flushing the transfer queue)", from_.label());
}

void MpiSendLink::post() {
    if (posted_) return;
    read_.wait(what() + ": reading them into pinned memory");
    if (channel_.alarm) channel_.alarm->check();  // a given-up step sends nothing more
    mpi::isend_bytes(staging_->data(), n_ * ParticleArrays::kBytesPerParticle, channel_.chunk_bytes, channel_.peer,
                     payload_tag(channel_), channel_.comm, requests_, what());
    posted_ = true;
}

void MpiSendLink::wait() {
    post();
    mpi::wait_all(requests_, what(), channel_.alarm);
}

// ---- the receiver's half ----

MpiReceiveLink::MpiReceiveLink(cl_rt::Device& to, const MpiChannel& channel)
    : to_(to), channel_(channel), staging_(std::make_unique<cl_rt::PinnedHost>()) {
    check_channel(channel_, "receive");
}

MpiReceiveLink::~MpiReceiveLink() {
    if (state_ == State::count_posted) {
        // Nothing may ever match it: cancelled, which completes at once for a receive.
        for (MPI_Request& r : requests_) {
            MPI_Cancel(&r);
            MPI_Wait(&r, MPI_STATUS_IGNORE);
        }
        requests_.clear();
    }
    if (std::uncaught_exceptions() == 0) {
        try {
            mpi::wait_all(requests_, what(), channel_.alarm);
            writing_.wait(what() + ": writing them into the device");
            return;
        } catch (const std::exception&) {
        }
    }
    if (!writing_.empty()) static_cast<void>(staging_.release());  // the device may still be reading it
    let_go(requests_, staging_, true);
}

std::string MpiReceiveLink::what() const {
    return "receiving " + (state_ == State::count_posted ? std::string("the count of particles")
                                                           : std::to_string(n_) + " particles") +
           " from rank " + std::to_string(channel_.peer) + " over link " + std::to_string(channel_.link);
}

void MpiReceiveLink::post() {
    if (state_ == State::count_posted) return;
    if (state_ == State::payload_posted)
        throw Error(what() + ": the next count's receive posted before receive() took these");
    MPI_Request r = MPI_REQUEST_NULL;
    mpi::check(MPI_Irecv(&count_message_, 1, MPI_UINT64_T, channel_.peer, count_tag(channel_), channel_.comm, &r),
               "MPI_Irecv", what() + ": the count");
    requests_.push_back(r);
    state_ = State::count_posted;
}

std::size_t MpiReceiveLink::wait_count() {
    if (state_ == State::payload_posted) return n_;
    post();
    mpi::wait_all(requests_, what(), channel_.alarm);
    constexpr std::uint64_t kMost = std::numeric_limits<std::size_t>::max() / ParticleArrays::kBytesPerParticle;
    if (count_message_ > kMost)
        throw Error("receiving particles from rank " + std::to_string(channel_.peer) + " over link " +
                    std::to_string(channel_.link) + ": it announced " + std::to_string(count_message_) +
                    ", more than any memory holds");
    n_ = static_cast<std::size_t>(count_message_);
    state_ = State::payload_posted;
    if (n_ == 0) return 0;
    writing_.wait(what() + ": the last receive's writes out of pinned memory");
    staging_->reserve(to_, n_ * ParticleArrays::kBytesPerParticle);
    mpi::irecv_bytes(staging_->data(), n_ * ParticleArrays::kBytesPerParticle, channel_.chunk_bytes, channel_.peer,
                     payload_tag(channel_), channel_.comm, requests_, what());
    return n_;
}

void MpiReceiveLink::receive(ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) {
    wait_count();
    mpi::wait_all(requests_, what(), channel_.alarm);
    state_ = State::idle;
    const std::size_t capacity = dst.capacity();
    if (to > capacity || n_ > capacity - to)
        throw Error(what() + ": they would go to [" + std::to_string(to) + ", " + std::to_string(to) + " + " +
                    std::to_string(n_) + ") of arrays with room for " + std::to_string(capacity) +
                    " particles (nothing written)");
    if (n_ == 0) return;
    device::write_particles(to_, dst, to, n_, staging_->data(), writing_, cl_rt::Device::On::transfer);
    for (cl::Event& e : writing_.events_of(to_)) received.add(to_, e);
    cl_rt::check(to_.transfer_queue().flush(), what() + " (flushing the transfer queue)", to_.label());
}

}  // namespace clsph::multi
