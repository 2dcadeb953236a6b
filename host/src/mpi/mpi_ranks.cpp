// Ranks over MPI (clsph/ranks.hpp, multi/ranks.hpp): the collectives on clsph's own communicator,
// the links' halves as MpiSendLink / MpiReceiveLink.
#include "clsph/error.hpp"
#include "clsph/ranks.hpp"
#include "mpi/environment.hpp"
#include "mpi/link.hpp"
#include "mpi/messages.hpp"
#include "multi/ranks.hpp"

namespace clsph {
namespace {

class MpiSend final : public multi::RemoteSendLink {
public:
    MpiSend(cl_rt::Device& d, const multi::MpiChannel& c) : link_(d, c) {}
    void send(const device::ParticleArrays& src, std::size_t first, std::size_t n) override { link_.send(src, first, n); }
    void post() override { link_.post(); }

private:
    multi::MpiSendLink link_;
};

class MpiReceive final : public multi::RemoteReceiveLink {
public:
    MpiReceive(cl_rt::Device& d, const multi::MpiChannel& c) : link_(d, c) { link_.post(); }
    std::size_t wait_count() override { return link_.wait_count(); }
    void receive(device::ParticleArrays& dst, std::size_t to, cl_rt::EventSet& received) override {
        link_.receive(dst, to, received);
        link_.post();  // the next step's count may come early
    }
    std::size_t count() const override { return link_.count(); }

private:
    multi::MpiReceiveLink link_;
};

class MpiRanks final : public Ranks {
public:
    MpiRanks(int& argc, char**& argv) : env_(std::make_shared<mpi::Environment>(argc, argv)), comm_(env_->comm()) {}
    // A duplicate of `comm` (errors returned, as the original's), freed with this object.
    MpiRanks(std::shared_ptr<mpi::Environment> env, MPI_Comm comm) : env_(std::move(env)), comm_(comm), owns_comm_(true) {}
    ~MpiRanks() override {
        if (owns_comm_) MPI_Comm_free(&comm_);
    }
    MpiRanks(const MpiRanks&) = delete;
    MpiRanks& operator=(const MpiRanks&) = delete;
    const multi::RankPlace& place() const override { return env_->place(); }

    std::shared_ptr<Ranks> fork() override {
        MPI_Comm dup = MPI_COMM_NULL;
        mpi::check(MPI_Comm_dup(comm_, &dup), "MPI_Comm_dup", "a communicator for a simulation");
        return std::make_shared<MpiRanks>(env_, dup);
    }

    void sum(std::vector<double>& v) override { reduce(v.data(), v.size(), MPI_DOUBLE, MPI_SUM, "sum"); }
    void sum(std::vector<std::uint64_t>& v) override { reduce(v.data(), v.size(), MPI_UINT64_T, MPI_SUM, "sum"); }
    void max(std::vector<double>& v) override { reduce(v.data(), v.size(), MPI_DOUBLE, MPI_MAX, "maximum"); }

    std::vector<std::uint64_t> gather_all(const std::vector<std::uint64_t>& mine) override {
        std::vector<std::uint64_t> all(mine.size() * static_cast<std::size_t>(size()));
        mpi::check(MPI_Allgather(mine.data(), count(mine.size()), MPI_UINT64_T, all.data(), count(mine.size()),
                                 MPI_UINT64_T, comm_),
                   "MPI_Allgather", "gathering the slabs' figures");
        return all;
    }

    std::vector<std::string> gather_text(const std::string& mine) override {
        const auto lengths = gather_all({static_cast<std::uint64_t>(mine.size())});
        std::vector<int> counts, at;
        int total = 0;
        for (auto n : lengths) {
            counts.push_back(count(n));
            at.push_back(total);
            total += counts.back();
        }
        std::string all(static_cast<std::size_t>(total), '\0');
        mpi::check(MPI_Allgatherv(mine.data(), count(mine.size()), MPI_CHAR, all.data(), counts.data(), at.data(), MPI_CHAR,
                                  comm_),
                   "MPI_Allgatherv", "gathering text from the ranks");
        std::vector<std::string> out;
        for (std::size_t r = 0; r < counts.size(); ++r)
            out.push_back(all.substr(static_cast<std::size_t>(at[r]), static_cast<std::size_t>(counts[r])));
        return out;
    }

    std::vector<std::string> gather_text_to(const std::string& mine, int root) override {
        // The lengths to the root, then the bytes as messages of any size (a checkpoint's slabs may
        // pass INT_MAX), on the communicator's largest tag, which no link's tags reach (2k, 2k + 1
        // for link k, checked against the same limit).
        const std::uint64_t length = mine.size();
        const bool here = rank() == root;
        std::vector<std::uint64_t> lengths(here ? static_cast<std::size_t>(size()) : 0);
        mpi::check(MPI_Gather(&length, 1, MPI_UINT64_T, lengths.data(), 1, MPI_UINT64_T, root, comm_), "MPI_Gather",
                   "gathering lengths to one rank");
        const int tag = mpi::tag_limit(comm_);
        const std::string what = "gathering data to rank " + std::to_string(root);
        std::vector<MPI_Request> requests;
        std::vector<std::string> out;
        if (!here) {
            mpi::isend_bytes(mine.data(), mine.size(), mpi::kDefaultChunk, root, tag, comm_, requests, what);
        } else {
            out.resize(lengths.size());
            for (std::size_t r = 0; r < lengths.size(); ++r) {
                if (static_cast<int>(r) == root) {
                    out[r] = mine;
                    continue;
                }
                out[r].resize(static_cast<std::size_t>(lengths[r]));
                mpi::irecv_bytes(out[r].data(), out[r].size(), mpi::kDefaultChunk, static_cast<int>(r), tag, comm_,
                                 requests, what);
            }
        }
        mpi::wait_all(requests, what);
        return out;
    }

    void broadcast(std::vector<std::uint64_t>& v, int root) override {
        mpi::check(MPI_Bcast(v.data(), count(v.size()), MPI_UINT64_T, root, comm_), "MPI_Bcast",
                   "broadcasting the cuts");
    }

    std::unique_ptr<multi::RemoteSendLink> sender(cl_rt::Device& device, int peer, int link) override {
        return std::make_unique<MpiSend>(device, multi::MpiChannel{comm_, peer, link});
    }
    std::unique_ptr<multi::RemoteReceiveLink> receiver(cl_rt::Device& device, int peer, int link) override {
        return std::make_unique<MpiReceive>(device, multi::MpiChannel{comm_, peer, link});
    }

    [[noreturn]] void abort(int code, const std::string& message) const override { mpi::abort(code, message); }

private:
    static int count(std::size_t n) {
        if (n > 1u << 30) throw Error("MPI collective of " + std::to_string(n) + " elements: too many");
        return static_cast<int>(n);
    }
    void reduce(void* data, std::size_t n, MPI_Datatype type, MPI_Op op, const char* what) {
        if (n == 0) return;
        mpi::check(MPI_Allreduce(MPI_IN_PLACE, data, count(n), type, op, comm_), "MPI_Allreduce",
                   std::string("the ") + what + " over the ranks");
    }
    std::shared_ptr<mpi::Environment> env_;
    MPI_Comm comm_ = MPI_COMM_NULL;
    bool owns_comm_ = false;
};

}  // namespace

std::shared_ptr<Ranks> mpi_ranks(int& argc, char**& argv) { return std::make_shared<MpiRanks>(argc, argv); }

}  // namespace clsph
