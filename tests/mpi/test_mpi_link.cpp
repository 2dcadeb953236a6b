// The MPI link between two ranks (mpi/link.hpp), run by mpiexec with 2 ranks: rank 0 fills
// random particles on its OpenCL device and sends random contiguous ranges (n = 0 and all of them
// among them); rank 1 receives them into poisoned arrays at random offsets and checks every word
// bitwise against the same random data, regenerated from the seed, and that nothing outside the
// received range was written. Over each pair of the devices present (with POCL_DEVICES="basic
// pthread" and RUSTICL_ENABLE=llvmpipe: pocl to pocl, pocl to rusticl, rusticl to pocl), with
// payloads in one message and in many small chunks.
//
// A rank giving up a step (Ranks::give_up): the other's waits end with RankFailure, and after
// recover() the ranks go on.
//
// `clsph-mpi-tests --abort-demo`: rank 1 fails while rank 0 waits for it; mpi::abort must stop both.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cl/device.hpp"
#include "clsph/build_info.hpp"
#include "clsph/error.hpp"
#include "clsph/ranks.hpp"
#include "device/particle_arrays.hpp"
#include "mpi/environment.hpp"
#include "mpi/messages.hpp"
#include "mpi/link.hpp"
#include "multi/ranks.hpp"

using namespace clsph;
using device::ParticleArrays;

namespace {

mpi::Environment* environment = nullptr;
constexpr std::uint32_t kPoison = 0xDEADBEEFu;

// Rank 0's seed ($CLSPH_TEST_SEED, else fresh), the same on every rank.
std::uint64_t seed() {
    static const std::uint64_t s = [] {
        std::uint64_t v = 0;
        if (environment->rank() == 0) {
            const char* env = std::getenv("CLSPH_TEST_SEED");
            v = env && *env ? std::strtoull(env, nullptr, 10)
                            : (std::uint64_t(std::random_device{}()) << 32) ^ std::random_device{}();
            std::cout << "[clsph mpi tests] seed " << v << " (rerun with CLSPH_TEST_SEED=" << v << ")" << std::endl;
        }
        mpi::check(MPI_Bcast(&v, 1, MPI_UINT64_T, 0, environment->comm()), "MPI_Bcast", "the seed");
        return v;
    }();
    return s;
}

// Every device of this node, opened once per rank (both ranks open them all, and take one each).
std::vector<cl_rt::Device*> devices() {
    static std::vector<std::unique_ptr<cl_rt::Device>> opened = [] {
        const char* env = std::getenv("CLSPH_TEST_DEVICES");
        auto d = cl_rt::open_devices(env && *env ? env : "all");
        if (environment->rank() == 0) {
            std::cout << "[clsph mpi tests] devices (each rank opens them all):";
            for (auto& dev : d) std::cout << "\n  " << dev->label();
            std::cout << std::endl;
        }
        return d;
    }();
    std::vector<cl_rt::Device*> out;
    for (auto& d : opened) out.push_back(d.get());
    return out;
}

// Runs this rank's part; an exception would leave the other rank waiting for messages that never
// come, so it stops both (the abort prints it).
void on_rank(const std::function<void()>& part) {
    try {
        part();
    } catch (const std::exception& e) {
        mpi::abort(1, std::string("unexpected exception in a test: ") + e.what());
    }
}

// The random words of `n` particles, in the staged block's order: [pos 4n | velrho 4n | accel 4n | id n].
std::vector<std::uint32_t> random_particles(std::uint64_t salt, std::size_t n) {
    std::mt19937_64 rng(seed() ^ (salt * 0x9E3779B97F4A7C15ull));
    std::vector<std::uint32_t> words(n * ParticleArrays::kBytesPerParticle / 4);
    for (auto& w : words) w = static_cast<std::uint32_t>(rng());
    return words;
}

// Fills are not blocking: finished before the transfer queue writes into the same arrays.
void poison(cl_rt::Device& device, ParticleArrays& a) {
    a.each([&](cl_rt::Buffer& b, std::size_t elem, const char*) { device.fill(b, kPoison, a.capacity() * elem / 4); });
    device.finish();
}

// Arrays of `capacity` particles on `device`, holding `words` (a block as above) or poison.
ParticleArrays make_arrays(cl_rt::Device& device, std::size_t capacity, const std::vector<std::uint32_t>* words) {
    ParticleArrays a;
    a.allocate(device, capacity, "mpi link test");
    std::size_t at = 0;
    a.each([&](cl_rt::Buffer& b, std::size_t elem, const char*) {
        const std::size_t n = capacity * elem / 4;
        if (words) device.write(b, words->data() + at, n);  // blocking
        at += n;
    });
    if (!words) poison(device, a);
    return a;
}

// Checks every word of `dst`: particles [to, to + n) are `src_words`' [first, first + n), the rest poison.
void check_arrays(cl_rt::Device& device, ParticleArrays& dst, const std::vector<std::uint32_t>& src_words,
                  std::size_t src_capacity, std::size_t first, std::size_t to, std::size_t n) {
    const std::size_t capacity = dst.capacity();
    std::size_t src_at = 0, bad = 0;
    std::string first_bad;
    dst.each([&](cl_rt::Buffer& b, std::size_t elem, const char* name) {
        const std::size_t w = elem / 4;
        std::vector<std::uint32_t> got(capacity * w);
        device.read(b, got.data(), got.size());
        for (std::size_t i = 0; i < capacity; ++i) {
            const bool inside = i >= to && i < to + n;
            for (std::size_t j = 0; j < w; ++j) {
                const std::uint32_t want = inside ? src_words[src_at + (first + i - to) * w + j] : kPoison;
                if (got[i * w + j] == want) continue;
                if (bad++ == 0)
                    first_bad = std::string(name) + " of particle " + std::to_string(i) + " word " + std::to_string(j) +
                                (inside ? " (received)" : " (outside the received range)") + ": got " +
                                std::to_string(got[i * w + j]) + ", want " + std::to_string(want);
            }
        }
        src_at += src_capacity * w;
    });
    INFO("first difference: " << first_bad);
    CHECK(bad == 0);
}

std::string device_pair(cl_rt::Device& a, cl_rt::Device& b) { return a.label() + " -> " + b.label(); }

}  // namespace

TEST_CASE("mpi: the environment: two ranks on one node, MPI_THREAD_MULTIPLE, errors as clsph::Error") {
    const mpi::Environment& env = *environment;
    REQUIRE(env.size() == 2);
    CHECK(env.local_size() == 2);
    CHECK(env.local_rank() == env.rank());
    int level = 0;
    MPI_Query_thread(&level);
    CHECK(level == MPI_THREAD_MULTIPLE);
    int same = MPI_UNEQUAL;
    MPI_Comm_compare(env.comm(), MPI_COMM_WORLD, &same);
    CHECK(same == MPI_CONGRUENT);  // a copy, not MPI_COMM_WORLD itself
    CHECK(built_with_mpi());
    CHECK(!mpi_library_version().empty());
    int x = 0;
    CHECK_THROWS_WITH_AS(mpi::check(MPI_Send(&x, 1, MPI_INT, 99, 0, env.comm()), "MPI_Send", "to nowhere"),
                         doctest::Contains("MPI_Send (to nowhere) failed: MPI_ERR_RANK"), Error);
    cl_rt::Device& d = *devices().front();
    CHECK_THROWS_WITH_AS((multi::MpiSendLink(d, {env.comm(), 2, 0})), doctest::Contains("rank 2 is not one of the 2"), Error);
    CHECK_THROWS_WITH_AS((multi::MpiReceiveLink(d, {env.comm(), 0, -1})), doctest::Contains("link -1"), Error);
    CHECK_THROWS_WITH_AS((multi::MpiReceiveLink(d, {env.comm(), 0, 1, 0})), doctest::Contains("a chunk"), Error);
    CHECK(mpi::chunks(0, 10) == 0);
    CHECK(mpi::chunks(10, 10) == 1);
    CHECK(mpi::chunks(11, 10) == 2);
    CHECK(mpi::chunks(std::size_t(5) << 30, mpi::kDefaultChunk) == 5);
}

TEST_CASE("mpi: random ranges of particles from rank 0 to rank 1, bitwise, over each pair of devices") {
    const auto devs = devices();
    const std::size_t kSource = 3000, kDestination = 3500, kRounds = 7;
    const auto words = random_particles(1, kSource);
    for (std::size_t k = 0; k < devs.size(); ++k) {
        cl_rt::Device& from = *devs[k];
        cl_rt::Device& to = *devs[(k + 1) % devs.size()];
        // One message per payload, then many small chunks of a size no particle divides.
        for (const std::size_t chunk : {mpi::kDefaultChunk, std::size_t(4093)}) {
            CAPTURE(device_pair(from, to));
            CAPTURE(chunk);
            const int link = static_cast<int>(k);
            // The rounds' draws, the same on both ranks.
            std::mt19937_64 rounds(seed() ^ (k * 2 + (chunk == mpi::kDefaultChunk)));
            on_rank([&] {
                if (environment->rank() == 0) {
                    ParticleArrays src = make_arrays(from, kSource, &words);
                    multi::MpiSendLink send(from, {environment->comm(), 1, link, chunk});
                    for (std::size_t round = 0; round < kRounds; ++round) {
                        const std::size_t n = round == 0 ? 0 : round == 1 ? kSource : round == 2 ? 1 : rounds() % kSource;
                        const std::size_t first = rounds() % (kSource - n + 1);
                        static_cast<void>(rounds());  // the receiver's offset
                        send.send(src, first, n);
                        CHECK(send.count() == n);
                        send.post();
                        send.wait();
                    }
                } else {
                    ParticleArrays dst = make_arrays(to, kDestination, nullptr);
                    multi::MpiReceiveLink receive(to, {environment->comm(), 0, link, chunk});
                    for (std::size_t round = 0; round < kRounds; ++round) {
                        CAPTURE(round);
                        const std::size_t n = round == 0 ? 0 : round == 1 ? kSource : round == 2 ? 1 : rounds() % kSource;
                        const std::size_t first = rounds() % (kSource - n + 1);
                        const std::size_t at = rounds() % (kDestination - n + 1);
                        poison(to, dst);
                        receive.post();
                        REQUIRE(receive.wait_count() == n);
                        cl_rt::EventSet received;
                        receive.receive(dst, at, received);
                        received.wait("the test's received particles");
                        check_arrays(to, dst, words, kSource, first, at, n);
                    }
                }
            });
        }
    }
}

TEST_CASE("mpi: a count larger than the destination's room is a clear error, nothing written, the link still usable") {
    const auto devs = devices();
    cl_rt::Device& device = *devs[static_cast<std::size_t>(environment->rank()) % devs.size()];
    const std::size_t kSource = 400, kRoom = 200;
    const auto words = random_particles(2, kSource);
    on_rank([&] {
        if (environment->rank() == 0) {
            ParticleArrays src = make_arrays(device, kSource, &words);
            multi::MpiSendLink send(device, {environment->comm(), 1, 7});
            send.send(src, 0, 300);  // more than the room
            send.send(src, 10, 100);  // fits, but not where the receiver puts it
            send.send(src, 20, 50);   // fits
            send.wait();
            CHECK_THROWS_WITH_AS(send.send(src, 390, 11), doctest::Contains("the arrays hold 400"), Error);
        } else {
            ParticleArrays dst = make_arrays(device, kRoom, nullptr);
            multi::MpiReceiveLink receive(device, {environment->comm(), 0, 7});
            cl_rt::EventSet received;
            CHECK(receive.wait_count() == 300);
            CHECK_THROWS_WITH_AS(receive.receive(dst, 0, received),
                                 doctest::Contains("receiving 300 particles from rank 0 over link 7: they would go to [0, 0 + "
                                                   "300) of arrays with room for 200 particles (nothing written)"),
                                 Error);
            CHECK(received.empty());
            CHECK(receive.wait_count() == 100);
            CHECK_THROWS_WITH_AS(receive.receive(dst, 150, received), doctest::Contains("room for 200"), Error);
            check_arrays(device, dst, words, kSource, 0, 0, 0);  // all poison
            CHECK(receive.wait_count() == 50);
            receive.receive(dst, 150, received);
            received.wait("the test's received particles");
            check_arrays(device, dst, words, kSource, 20, 150, 50);
        }
    });
}

TEST_CASE("mpi: a block of more than INT_MAX bytes (set CLSPH_TEST_MPI_LARGE=1: 2 GiB of memory a rank)") {
    const char* large = std::getenv("CLSPH_TEST_MPI_LARGE");
    if (!large || std::string(large) != "1") return;
    const std::size_t bytes = (std::size_t(1) << 31) + 4099;
    std::vector<unsigned char> block(bytes);
    std::vector<MPI_Request> requests;
    on_rank([&] {
        if (environment->rank() == 0) {
            for (std::size_t i = 0; i < bytes; ++i) block[i] = static_cast<unsigned char>(i * 2654435761u >> 13);
            mpi::isend_bytes(block.data(), bytes, mpi::kDefaultChunk, 1, 5, environment->comm(), requests, "large");
            CHECK(requests.size() == 3);
            mpi::wait_all(requests, "large");
        } else {
            mpi::irecv_bytes(block.data(), bytes, mpi::kDefaultChunk, 0, 5, environment->comm(), requests, "large");
            mpi::wait_all(requests, "large");
            std::size_t bad = 0;
            for (std::size_t i = 0; i < bytes; ++i) bad += block[i] != static_cast<unsigned char>(i * 2654435761u >> 13);
            CHECK(bad == 0);
        }
    });
}

// The alarm (mpi/alarm.hpp) through the Ranks: rank 1 gives the step up while rank 0 waits for
// its count on a link; rank 0's wait and then its collective throw RankFailure naming rank 1 and
// its error, as do rank 1's own waits; after recover() the ranks go on together, while the failed
// run's Ranks stays given up (and its link is destroyed without waiting).
TEST_CASE("mpi: a rank giving up the step: the other's waits throw RankFailure; after recover the ranks go on") {
    int argc = 0;
    char** argv = nullptr;
    const std::shared_ptr<Ranks> ranks = mpi_ranks(argc, argv);
    const std::shared_ptr<Ranks> run = ranks->fork();
    const int rank = ranks->rank();
    const std::string why = "step 7: a deliberate failure (the alarm test)";
    {
        std::unique_ptr<multi::RemoteReceiveLink> link;
        if (rank == 0) link = run->receiver(*devices().front(), 1, 0);
        if (rank == 1) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));  // rank 0 is waiting by now
            give_up(*ranks, why);
        } else {
            CHECK_THROWS_WITH_AS(link->wait_count(), doctest::Contains(("rank 1 of 2: " + why).c_str()), RankFailure);
        }
        std::vector<double> v{1.0};
        try {
            run->sum(v);
            FAIL("the sum went through");
        } catch (const RankFailure& e) {
            CHECK(e.rank() == 1);
            CHECK(std::string(e.what()) == "rank 1 of 2: " + why);
        }
    }
    recover(*ranks);
    const std::shared_ptr<Ranks> next = ranks->fork();
    std::vector<double> v{static_cast<double>(rank + 1)};
    next->sum(v);
    CHECK(v[0] == 3.0);
    CHECK(next->gather_text(std::to_string(rank)) == std::vector<std::string>{"0", "1"});
    std::vector<double> w{1.0};
    CHECK_THROWS_AS(run->sum(w), RankFailure);
}

int main(int argc, char** argv) {
    try {
        mpi::Environment env(argc, argv);
        environment = &env;
        for (int i = 1; i < argc; ++i) {
            if (std::strcmp(argv[i], "--abort-demo") != 0) continue;
            if (env.rank() == 1) mpi::abort(3, "a deliberate failure (the abort test)");
            int never = 0;  // rank 0 waits for a message rank 1 never sends: only the abort ends it
            MPI_Recv(&never, 1, MPI_INT, 1, 0, env.comm(), MPI_STATUS_IGNORE);
            return 0;
        }
        doctest::Context context(argc, argv);
        int failed = 0;
        on_rank([&] { failed = context.run(); });
        if (context.shouldExit()) return failed;
        int any = 0;  // the verdict of every rank
        mpi::check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, env.comm()), "MPI_Allreduce", "the verdicts");
        return any;
    } catch (const std::exception& e) {
        mpi::abort(1, e.what());
    }
}
