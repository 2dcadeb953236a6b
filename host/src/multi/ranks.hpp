// What the slab driver needs of the ranks one run spans (clsph/ranks.hpp): where this process
// stands, a few collectives over small host arrays, and the two halves of a link to a slab on
// another rank. One implementation: MPI (host/src/mpi/mpi_ranks.cpp); one process needs none.
#pragma once
#include "cl/device.hpp"
#include "multi/link.hpp"
#include "multi/rank_devices.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace clsph {

class Ranks {
public:
    virtual ~Ranks() = default;
    virtual const multi::RankPlace& place() const = 0;
    int rank() const { return place().rank; }
    int size() const { return place().size; }

    // Element-wise over every rank, in place (the same length on every rank).
    virtual void sum(std::vector<double>& v) = 0;
    virtual void sum(std::vector<std::uint64_t>& v) = 0;
    virtual void max(std::vector<double>& v) = 0;
    // Every rank's `mine` (the same length on every rank), in rank order.
    virtual std::vector<std::uint64_t> gather_all(const std::vector<std::uint64_t>& mine) = 0;
    // Every rank's text, in rank order (any lengths).
    virtual std::vector<std::string> gather_text(const std::string& mine) = 0;
    // Every rank's text on rank `root` only, in rank order (any lengths); empty on the others.
    virtual std::vector<std::string> gather_text_to(std::string mine, int root) = 0;
    // Rank `root`'s `v` on every rank (the same length on every rank).
    virtual void broadcast(std::vector<std::uint64_t>& v, int root) = 0;

    // The halves of link number `link` (the same number on both ranks) between a slab of this
    // rank on `device` and a slab of rank `peer`.
    virtual std::unique_ptr<multi::RemoteSendLink> sender(cl_rt::Device& device, int peer, int link) = 0;
    virtual std::unique_ptr<multi::RemoteReceiveLink> receiver(cl_rt::Device& device, int peer, int link) = 0;

    [[noreturn]] virtual void abort(int code, const std::string& message) const = 0;

    // This rank cannot finish the step (`why`: its error): every wait of the run, on every rank,
    // throws RankFailure from now on instead of waiting for it (mpi/alarm.hpp). Once per failure;
    // later calls do nothing.
    virtual void give_up(const std::string& why) = 0;
    // After a failure, on every rank (collective): fresh communicators and a fresh alarm for
    // this Ranks, so that what the given-up step left in flight meets nothing of what follows.
    // The Ranks forked before (the failed run's) keep the old ones, which stay gone off.
    virtual void recover() = 0;

    // The same ranks on a communicator of their own (collective: every rank calls it, in the same
    // order): each Simulation's links and collectives then never meet another's, whose messages
    // carry the same tags.
    virtual std::shared_ptr<Ranks> fork() = 0;
};

}  // namespace clsph
