// The devices a run's chain of slabs spans, one process or across MPI ranks (clsph/memory_plan.hpp).
#pragma once
#include "cl/device.hpp"
#include "clsph/memory_plan.hpp"

#include <string>

namespace clsph::simulation {

// This rank's own devices of `spec` (dealt from the node's, or its clause of a per-rank spec), as
// a spec of indices.
std::string rank_spec(const std::string& spec, const Ranks& ranks);
// The chain's devices for `spec` (collective across `ranks`; null: one process).
ChainDevices chain_devices(const std::string& spec, const cl_rt::OpenOptions& open, Ranks* ranks);

}  // namespace clsph::simulation
