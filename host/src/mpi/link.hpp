// A link between slabs on two ranks (issue 21): the in-process StagedLink (link.hpp) cut in two
// halves, one per rank, with MPI between their pinned host stagings (GPU-aware MPI is not assumed).
//
//   sender's rank                                  receiver's rank
//   MpiSendLink::send(src, first, n)               MpiReceiveLink::post()      (early: before the sort)
//     count -> peer at once; device read of          the count's receive is posted
//     [first, first + n) into pinned staging       MpiReceiveLink::wait_count() -> n
//     on the transfer queue                          (plan where they go); the payload's receives
//   ... device work ...                              are posted into pinned staging
//   MpiSendLink::post()                            ... device work ...
//     waits for the read, posts the payload        MpiReceiveLink::receive(dst, to, received)
//   MpiSendLink::wait()  (before the next send)      waits for the payload, enqueues its write into
//                                                    dst [to, to + n) on the transfer queue
//
// Every call returns without waiting for the other rank except wait(), wait_count() and
// receive(), so the messages travel while the devices work. Each half is used by one host thread
// at a time. A payload of more than INT_MAX bytes goes in chunks (mpi/messages.hpp).
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "device/particle_arrays.hpp"
#include "mpi/messages.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace clsph::multi {

// Whom one half talks to: `peer` in `comm` (which returns errors: mpi::Environment::comm()), over
// the link numbered `link` (its messages carry tags 2 link and 2 link + 1, so the links between
// two ranks never take each other's). Both halves give the same link and chunk.
struct MpiChannel {
    MPI_Comm comm = MPI_COMM_NULL;
    int peer = 0;
    int link = 0;
    std::size_t chunk_bytes = mpi::kDefaultChunk;
    // The run's alarm (mpi/alarm.hpp): the waits throw RankFailure once a rank has given up the
    // step. Null: they wait as long as it takes.
    mpi::Alarm* alarm = nullptr;
};

class MpiSendLink {
public:
    MpiSendLink(cl_rt::Device& from, const MpiChannel& channel);
    // Waits for messages still in flight, unless an exception is unwinding (then the run is about
    // to abort: the requests are let go and the staging left allocated, as MPI may still read it).
    ~MpiSendLink();
    MpiSendLink(const MpiSendLink&) = delete;
    MpiSendLink& operator=(const MpiSendLink&) = delete;

    // Posts the count to the peer and enqueues reading particles [first, first + n) of `src` into
    // pinned staging on the transfer queue; returns at once. `src` must hold them already (its
    // compute queue's work on them complete) and keep them until post() has returned. Waits for
    // the previous send's messages first (wait()).
    void send(const device::ParticleArrays& src, std::size_t first, std::size_t n);
    // Waits for the read, then posts the payload; returns without waiting for the peer.
    void post();
    // Blocks until MPI is done with the staging (posting the payload first if need be).
    void wait();
    // Particles of the last send().
    std::size_t count() const { return n_; }

private:
    std::string what() const;
    cl_rt::Device& from_;
    MpiChannel channel_;
    std::unique_ptr<cl_rt::PinnedHost> staging_;
    cl_rt::EventSet read_;
    std::vector<MPI_Request> requests_;
    std::uint64_t count_message_ = 0;  // the count's send buffer: lives until it has gone
    std::size_t n_ = 0;
    bool posted_ = true;
};

class MpiReceiveLink {
public:
    MpiReceiveLink(cl_rt::Device& to, const MpiChannel& channel);
    // Cancels a receive nothing has matched yet; otherwise as ~MpiSendLink.
    ~MpiReceiveLink();
    MpiReceiveLink(const MpiReceiveLink&) = delete;
    MpiReceiveLink& operator=(const MpiReceiveLink&) = delete;

    // Posts the receive of the next count; returns at once. (wait_count() posts it if not yet.)
    void post();
    // Blocks until the count has come, posts the payload's receives into pinned staging (grown as
    // needed, once the last receive's writes out of it have completed) and returns the count.
    std::size_t wait_count();
    // Blocks until the payload has come, then enqueues writing it into `dst` at [to, to + n) on
    // the transfer queue; `received` gets the events (the compute queue waits for them with a
    // barrier). Throws clsph::Error, writing nothing, when `dst` has no room for them there (the
    // messages are taken all the same, so the link stays usable).
    void receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received);
    // Particles of the last wait_count().
    std::size_t count() const { return n_; }

private:
    std::string what() const;
    enum class State { idle, count_posted, payload_posted };
    cl_rt::Device& to_;
    MpiChannel channel_;
    std::unique_ptr<cl_rt::PinnedHost> staging_;
    cl_rt::EventSet writing_;  // the last receive's writes out of the staging
    std::vector<MPI_Request> requests_;
    std::uint64_t count_message_ = 0;
    std::size_t n_ = 0;
    State state_ = State::idle;
};

}  // namespace clsph::multi
