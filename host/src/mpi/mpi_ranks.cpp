// Ranks over MPI (clsph/ranks.hpp, multi/ranks.hpp): the collectives on clsph's own communicator,
// the links' halves as MpiSendLink / MpiReceiveLink.
#include "clsph/error.hpp"
#include "clsph/ranks.hpp"
#include "mpi/alarm.hpp"
#include "mpi/environment.hpp"
#include "mpi/link.hpp"
#include "mpi/messages.hpp"
#include "multi/ranks.hpp"

#include <algorithm>
#include <cstring>

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

// A collective's buffers on the heap: freed once it has completed, let go (never freed) when a
// given-up step leaves it in flight.
class Held {
public:
    Held() = default;
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;
    ~Held() {
        if (kept_) return;
        for (auto* p : parts_) delete p;
    }
    template <class T>
    T* make(std::size_t n) {
        parts_.push_back(new std::string(std::max<std::size_t>(n, 1) * sizeof(T), '\0'));
        return reinterpret_cast<T*>(parts_.back()->data());
    }
    template <class T>
    T* copy(const T* from, std::size_t n) {
        T* to = make<T>(n);
        if (n) std::memcpy(static_cast<void*>(to), from, n * sizeof(T));
        return to;
    }
    std::string* take(std::string s) {
        parts_.push_back(new std::string(std::move(s)));
        return parts_.back();
    }
    void let_go() { kept_ = true; }

private:
    std::vector<std::string*> parts_;
    bool kept_ = false;
};

class MpiRanks final : public Ranks {
public:
    MpiRanks(int& argc, char**& argv)
        : env_(std::make_shared<mpi::Environment>(argc, argv)),
          comm_(env_->comm()),
          alarm_(std::make_shared<mpi::Alarm>(env_->base())) {}
    // A duplicate of `comm` (errors returned, as the original's), freed with this object.
    MpiRanks(std::shared_ptr<mpi::Environment> env, MPI_Comm comm, std::shared_ptr<mpi::Alarm> alarm)
        : env_(std::move(env)), comm_(comm), owns_comm_(true), alarm_(std::move(alarm)) {}
    ~MpiRanks() override { free_comm(); }
    MpiRanks(const MpiRanks&) = delete;
    MpiRanks& operator=(const MpiRanks&) = delete;
    const multi::RankPlace& place() const override { return env_->place(); }

    std::shared_ptr<Ranks> fork() override {
        MPI_Comm dup = MPI_COMM_NULL;
        mpi::check(MPI_Comm_dup(comm_, &dup), "MPI_Comm_dup", "a communicator for a simulation");
        return std::make_shared<MpiRanks>(env_, dup, alarm_);
    }

    void give_up(const std::string& why) override { alarm_->raise(why); }

    void recover() override {
        // From the base communicator, which no operation of the given-up step touched.
        MPI_Comm fresh = MPI_COMM_NULL;
        mpi::check(MPI_Comm_dup(env_->base(), &fresh), "MPI_Comm_dup", "a fresh communicator after a failure");
        mpi::check(MPI_Comm_set_errhandler(fresh, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
        free_comm();
        alarm_ = std::make_shared<mpi::Alarm>(env_->base());
        comm_ = fresh;
        owns_comm_ = true;
    }

    void sum(std::vector<double>& v) override { reduce(v.data(), v.size(), MPI_DOUBLE, MPI_SUM, "sum"); }
    void sum(std::vector<std::uint64_t>& v) override { reduce(v.data(), v.size(), MPI_UINT64_T, MPI_SUM, "sum"); }
    void max(std::vector<double>& v) override { reduce(v.data(), v.size(), MPI_DOUBLE, MPI_MAX, "maximum"); }

    std::vector<std::uint64_t> gather_all(const std::vector<std::uint64_t>& mine) override {
        const std::string what = "gathering the slabs' figures";
        Held held;
        const auto* send = held.copy(mine.data(), mine.size());
        auto* all = held.make<std::uint64_t>(mine.size() * static_cast<std::size_t>(size()));
        MPI_Request r = MPI_REQUEST_NULL;
        mpi::check(MPI_Iallgather(send, count(mine.size()), MPI_UINT64_T, all, count(mine.size()), MPI_UINT64_T, comm_, &r),
                   "MPI_Iallgather", what);
        wait({r}, what, held);
        return {all, all + mine.size() * static_cast<std::size_t>(size())};
    }

    std::vector<std::string> gather_text(const std::string& mine) override {
        const std::string what = "gathering text from the ranks";
        const auto lengths = gather_all({static_cast<std::uint64_t>(mine.size())});
        Held held;
        auto* counts = held.make<int>(lengths.size());
        auto* at = held.make<int>(lengths.size());
        int total = 0;
        for (std::size_t r = 0; r < lengths.size(); ++r) {
            counts[r] = count(lengths[r]);
            at[r] = total;
            total += counts[r];
        }
        const char* send = held.copy(mine.data(), mine.size());
        char* all = held.make<char>(static_cast<std::size_t>(total));
        MPI_Request q = MPI_REQUEST_NULL;
        mpi::check(MPI_Iallgatherv(send, count(mine.size()), MPI_CHAR, all, counts, at, MPI_CHAR, comm_, &q),
                   "MPI_Iallgatherv", what);
        wait({q}, what, held);
        std::vector<std::string> out;
        for (std::size_t r = 0; r < lengths.size(); ++r)
            out.emplace_back(all + at[r], static_cast<std::size_t>(counts[r]));
        return out;
    }

    std::vector<std::string> gather_text_to(std::string mine, int root) override {
        // The lengths to the root, then the bytes as messages of any size (a checkpoint's slabs may
        // pass INT_MAX), on the communicator's largest tag, which no link's tags reach (2k, 2k + 1
        // for link k, checked against the same limit).
        const bool here = rank() == root;
        Held held;
        auto* length = held.make<std::uint64_t>(1);
        *length = mine.size();
        auto* lengths = held.make<std::uint64_t>(here ? static_cast<std::size_t>(size()) : 0);
        MPI_Request q = MPI_REQUEST_NULL;
        mpi::check(MPI_Igather(length, 1, MPI_UINT64_T, lengths, 1, MPI_UINT64_T, root, comm_, &q), "MPI_Igather",
                   "gathering lengths to one rank");
        wait({q}, "gathering lengths to one rank", held);
        const int tag = mpi::tag_limit(comm_);
        const std::string what = "gathering data to rank " + std::to_string(root);
        std::vector<MPI_Request> requests;
        std::vector<std::string*> parts(here ? static_cast<std::size_t>(size()) : 0, nullptr);
        if (!here) {
            const std::string* sent = held.take(std::move(mine));
            mpi::isend_bytes(sent->data(), sent->size(), mpi::kDefaultChunk, root, tag, comm_, requests, what);
        } else {
            for (std::size_t r = 0; r < parts.size(); ++r) {
                if (static_cast<int>(r) == root) continue;
                parts[r] = held.take(std::string(static_cast<std::size_t>(lengths[r]), '\0'));
                mpi::irecv_bytes(parts[r]->data(), parts[r]->size(), mpi::kDefaultChunk, static_cast<int>(r), tag, comm_,
                                 requests, what);
            }
        }
        wait(std::move(requests), what, held);
        std::vector<std::string> out(parts.size());
        for (std::size_t r = 0; r < parts.size(); ++r) out[r] = static_cast<int>(r) == root ? std::move(mine) : std::move(*parts[r]);
        return out;
    }

    void broadcast(std::vector<std::uint64_t>& v, int root) override {
        Held held;
        auto* data = held.copy(v.data(), v.size());
        MPI_Request r = MPI_REQUEST_NULL;
        mpi::check(MPI_Ibcast(data, count(v.size()), MPI_UINT64_T, root, comm_, &r), "MPI_Ibcast", "broadcasting the cuts");
        wait({r}, "broadcasting the cuts", held);
        std::copy(data, data + v.size(), v.begin());
    }

    std::unique_ptr<multi::RemoteSendLink> sender(cl_rt::Device& device, int peer, int link) override {
        return std::make_unique<MpiSend>(device, multi::MpiChannel{comm_, peer, link, mpi::kDefaultChunk, alarm_.get()});
    }
    std::unique_ptr<multi::RemoteReceiveLink> receiver(cl_rt::Device& device, int peer, int link) override {
        return std::make_unique<MpiReceive>(device, multi::MpiChannel{comm_, peer, link, mpi::kDefaultChunk, alarm_.get()});
    }

    [[noreturn]] void abort(int code, const std::string& message) const override { mpi::abort(code, message); }

private:
    static int count(std::size_t n) {
        if (n > 1u << 30) throw Error("MPI collective of " + std::to_string(n) + " elements: too many");
        return static_cast<int>(n);
    }
    // A communicator on which a given-up step may have left collectives is never freed: Open MPI
    // goes on progressing them, and on a freed communicator that crashes. Nothing uses it again.
    void free_comm() {
        if (alarm_->gone_off()) {
            if (!owns_comm_) env_->keep_comm();  // the Environment's own copy of MPI_COMM_WORLD
            return;
        }
        if (owns_comm_) MPI_Comm_free(&comm_);
    }
    template <class T>
    void reduce(T* data, std::size_t n, MPI_Datatype type, MPI_Op op, const char* what) {
        if (n == 0) return;
        Held held;
        T* in_flight = held.copy(data, n);
        MPI_Request r = MPI_REQUEST_NULL;
        mpi::check(MPI_Iallreduce(MPI_IN_PLACE, in_flight, count(n), type, op, comm_, &r), "MPI_Iallreduce",
                   std::string("the ") + what + " over the ranks");
        wait({r}, std::string("the ") + what + " over the ranks", held);
        std::copy(in_flight, in_flight + n, data);
    }
    // Every collective is non-blocking and waited for with the alarm, so that a rank that gave up
    // the step never leaves the others in one. A collective given up stays in flight (MPI lets
    // nothing cancel or free it; recover() replaces its communicator), and MPI may still touch its
    // buffers: they are let go, never freed.
    void wait(std::vector<MPI_Request> requests, const std::string& what, Held& held) {
        try {
            mpi::wait_all(requests, what, alarm_.get());
        } catch (const RankFailure&) {
            held.let_go();
            throw;
        }
    }
    std::shared_ptr<mpi::Environment> env_;
    MPI_Comm comm_ = MPI_COMM_NULL;
    bool owns_comm_ = false;
    std::shared_ptr<mpi::Alarm> alarm_;  // this run's, shared with its forks
};

}  // namespace

std::shared_ptr<Ranks> mpi_ranks(int& argc, char**& argv) { return std::make_shared<MpiRanks>(argc, argv); }

}  // namespace clsph
