#include "mpi/messages.hpp"

#include "clsph/error.hpp"
#include "mpi/environment.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <thread>

namespace clsph::mpi {
namespace {

int chunk_int(std::size_t chunk) {
    if (chunk == 0 || chunk > static_cast<std::size_t>(INT_MAX))
        throw Error("MPI messages of " + std::to_string(chunk) + " bytes: a chunk is 1 to INT_MAX bytes");
    return static_cast<int>(chunk);
}

template <class Post>
void each_chunk(std::size_t bytes, std::size_t chunk, Post&& post) {
    chunk_int(chunk);
    for (std::size_t at = 0; at < bytes; at += chunk) post(at, static_cast<int>(std::min(chunk, bytes - at)));
}

}  // namespace

std::size_t chunks(std::size_t bytes, std::size_t chunk) {
    chunk_int(chunk);
    return bytes / chunk + (bytes % chunk != 0);
}

void isend_bytes(const void* data, std::size_t bytes, std::size_t chunk, int peer, int tag, MPI_Comm comm,
                 std::vector<MPI_Request>& requests, const std::string& what) {
    const auto* p = static_cast<const unsigned char*>(data);
    each_chunk(bytes, chunk, [&](std::size_t at, int n) {
        MPI_Request r = MPI_REQUEST_NULL;
        check(MPI_Isend(p + at, n, MPI_BYTE, peer, tag, comm, &r), "MPI_Isend",
              what + ", bytes " + std::to_string(at) + "+" + std::to_string(n) + " of " + std::to_string(bytes) +
                  " to rank " + std::to_string(peer));
        requests.push_back(r);
    });
}

void irecv_bytes(void* data, std::size_t bytes, std::size_t chunk, int peer, int tag, MPI_Comm comm,
                 std::vector<MPI_Request>& requests, const std::string& what) {
    auto* p = static_cast<unsigned char*>(data);
    each_chunk(bytes, chunk, [&](std::size_t at, int n) {
        MPI_Request r = MPI_REQUEST_NULL;
        check(MPI_Irecv(p + at, n, MPI_BYTE, peer, tag, comm, &r), "MPI_Irecv",
              what + ", bytes " + std::to_string(at) + "+" + std::to_string(n) + " of " + std::to_string(bytes) +
                  " from rank " + std::to_string(peer));
        requests.push_back(r);
    });
}

bool test_all(std::vector<MPI_Request>& requests, const std::string& what) {
    if (requests.empty()) return true;
    int done = 0;
    std::vector<MPI_Status> statuses(requests.size());
    const int rc = MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, statuses.data());
    if (rc == MPI_ERR_IN_STATUS) {
        for (const MPI_Status& s : statuses)
            if (s.MPI_ERROR != MPI_SUCCESS && s.MPI_ERROR != MPI_ERR_PENDING) check(s.MPI_ERROR, "MPI_Testall", what);
    }
    check(rc, "MPI_Testall", what);
    if (done) requests.clear();
    return done != 0;
}

void wait_all(std::vector<MPI_Request>& requests, const std::string& what, Alarm* alarm) {
    for (int looks = 0; !test_all(requests, what); ++looks) {
        if (alarm) alarm->check();
        if (looks < 64) std::this_thread::yield();
        else std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
}

int tag_limit(MPI_Comm comm) {
    void* value = nullptr;
    int flag = 0;
    check(MPI_Comm_get_attr(comm, MPI_TAG_UB, &value, &flag), "MPI_Comm_get_attr", "MPI_TAG_UB");
    return flag ? *static_cast<int*>(value) : 32767;
}

}  // namespace clsph::mpi
