// Which of a node's OpenCL devices an MPI rank drives, when one run spans ranks (issue 21). Pure
// host logic: no MPI and no OpenCL types, so it is tested without either and compiled whether or
// not clsph is built with MPI.
//
// Two forms of the --devices spec:
//   * the usual one (clsph/devices.hpp: "gpu", "0,2", "platform:pocl", ...) names the devices of
//     the whole node; they are dealt to the ranks on that node (deal_devices);
//   * the per-rank form names each rank's own devices, clauses separated by ';':
//         rank0=gpu;rank1=cpu             rank 0 the node's GPUs, rank 1 its CPU devices
//         rank0=0;rank1-3=platform:pocl   ranges of ranks share a clause
//         rank0=gpu;*=cpu                 '*': every rank no other clause names
//     Right of '=' is the usual grammar, or 'none': the rank drives no device and takes part in
//     the run without slabs (what a rank whose devices all failed goes on with). Ranks are MPI_COMM_WORLD ranks; the devices a clause
//     selects are that rank's as they are (not dealt), so two ranks on one node that select the
//     same device share it. ';' and '=' appear in no term of the usual grammar, so a spec is
//     per-rank exactly when it contains '='.
#pragma once
#include "clsph/devices.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace clsph::multi {

// Where a rank stands: its rank and the number of ranks in the run, and the same among the ranks
// of its node (MPI_COMM_TYPE_SHARED).
struct RankPlace {
    int rank = 0, size = 1;
    int local_rank = 0, local_size = 1;
};

// The devices of `selected` (a node's selection, in order) that the rank `local_rank` of
// `local_size` on that node drives. With at least as many ranks as devices, one device each,
// round-robin: selected[local_rank % D] (ranks beyond D share). With more devices than ranks, a
// contiguous block each, as even as can be, earlier ranks taking the extra ones (5 devices over 2
// ranks: {0,1,2} and {3,4}). Throws DeviceSelectionError when `selected` is empty and Error when
// the place is impossible.
std::vector<std::size_t> deal_devices(const std::vector<std::size_t>& selected, int local_rank, int local_size);

// True when `spec` is of the per-rank form (it contains '=').
bool is_per_rank_spec(const std::string& spec);

// The usual spec that the per-rank `spec` gives `rank` (its own clause, else '*'). Throws
// DeviceSelectionError naming the bad clause (not rankN, rankN-M or *; no '='; nothing after '=';
// a rank named by two clauses) or saying that no clause names `rank`.
std::string spec_for_rank(const std::string& spec, int rank);

// This rank's devices (indices into `devices`, the node's list): a per-rank spec's clause
// selected as it is (none for 'none'), or the usual spec's selection dealt by deal_devices. Errors as
// select_devices, with the rank named.
std::vector<std::size_t> rank_devices(const std::vector<DeviceInfo>& devices, const std::string& spec,
                                      const RankPlace& place);

}  // namespace clsph::multi
