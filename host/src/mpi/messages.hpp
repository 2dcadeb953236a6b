// Non-blocking messages of any size, and waiting for them without spinning a core.
//
// MPI counts are int: a block of more than INT_MAX bytes goes as several messages of at most
// `chunk` bytes each, posted in order with one tag, and MPI keeps the order of one sender's
// messages on one communicator and tag, so the receiver's chunks (the same cut, from the same
// byte count and chunk size) match them one for one.
#pragma once
#include "mpi/alarm.hpp"

#include <mpi.h>

#include <cstddef>
#include <string>
#include <vector>

namespace clsph::mpi {

// 1 GiB: well under INT_MAX, and few messages for the largest blocks a device holds.
inline constexpr std::size_t kDefaultChunk = std::size_t(1) << 30;

// How many messages `bytes` takes (0 for none).
std::size_t chunks(std::size_t bytes, std::size_t chunk);

// Posts the messages of `bytes` from `data` to (from) `peer` with `tag`; appends their requests
// to `requests`. `what` goes into errors. The memory stays untouched until they have completed.
void isend_bytes(const void* data, std::size_t bytes, std::size_t chunk, int peer, int tag, MPI_Comm comm,
                 std::vector<MPI_Request>& requests, const std::string& what);
void irecv_bytes(void* data, std::size_t bytes, std::size_t chunk, int peer, int tag, MPI_Comm comm,
                 std::vector<MPI_Request>& requests, const std::string& what);

// Whether every request has completed (then `requests` is emptied); throws clsph::Error naming
// `what` and the failed request's error.
bool test_all(std::vector<MPI_Request>& requests, const std::string& what);
// Blocks until every request has completed; `requests` is empty afterwards. Polls MPI_Testall,
// yielding at first and then sleeping 20 us between looks (MPI_Waitall spins a core, which the
// devices' threads and a CPU device need), so MPI makes progress only while we look. With an
// `alarm`, each look also looks at it: once it has gone off (a rank gave up the step) the wait
// throws RankFailure, leaving the requests in flight to the caller (`requests` as it was).
void wait_all(std::vector<MPI_Request>& requests, const std::string& what, Alarm* alarm = nullptr);

// The largest tag the communicator allows (MPI_TAG_UB, at least 32767).
int tag_limit(MPI_Comm comm);

}  // namespace clsph::mpi
