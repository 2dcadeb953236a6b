// A Link moves one contiguous range of particles from one slab's device to another's, so the rest
// of the step never knows how: today through pinned host memory within one process (StagedLink);
// between processes it will be MPI. Both ends run on the devices' transfer queues, beside their
// compute work; send() and receive() are called from the sender's and the receiver's host threads.
#pragma once
#include "cl/async.hpp"
#include "cl/device.hpp"
#include "device/particle_arrays.hpp"

#include <cstddef>

namespace clsph::multi {

class Link {
public:
    virtual ~Link() = default;
    // Enqueues taking particles [first, first + n) of `src`, on the sender; `sent` gets the events.
    virtual void send(const device::ParticleArrays& src, std::size_t first, std::size_t n, cl_rt::EventSet& sent) = 0;
    // Once `sent` has been waited for: enqueues putting them into `dst` at `to`, on the receiver;
    // `received` gets the events (the receiver's compute queue waits for them with a barrier).
    virtual void receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) = 0;
    // Particles in flight: what the last send() took.
    virtual std::size_t count() const = 0;
};

// The halves of a link between slabs on two ranks (clsph/ranks.hpp; MPI: mpi/link.hpp), as the
// exchange uses them. The sender sends every step, n = 0 included, so the receiver always learns
// its count: send() posts the count and enqueues the device read; post() sends the particles once
// read. The receiver's wait_count() blocks until the count has come; receive() until the particles
// have, then enqueues their write into `dst` at `to`.
class RemoteSendLink {
public:
    virtual ~RemoteSendLink() = default;
    virtual void send(const device::ParticleArrays& src, std::size_t first, std::size_t n) = 0;
    virtual void post() = 0;
};

class RemoteReceiveLink {
public:
    virtual ~RemoteReceiveLink() = default;
    virtual std::size_t wait_count() = 0;
    virtual void receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) = 0;
    virtual std::size_t count() const = 0;
};

// Staging through pinned host memory of the sender's context (it works across contexts and
// vendors; the receiver's side measured the same: BENCHMARKS.md, second pass).
class StagedLink final : public Link {
public:
    StagedLink(cl_rt::Device& from, cl_rt::Device& to) : from_(from), to_(to) {}
    void send(const device::ParticleArrays& src, std::size_t first, std::size_t n, cl_rt::EventSet& sent) override;
    void receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) override;
    std::size_t count() const override { return n_; }

private:
    cl_rt::Device& from_;
    cl_rt::Device& to_;
    cl_rt::PinnedHost staging_;
    std::size_t n_ = 0;
};

}  // namespace clsph::multi
