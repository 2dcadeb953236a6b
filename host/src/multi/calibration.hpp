// Before the first step, with several devices and the dynamic balancer: each device is timed on
// samples of the scene, so devices of different speeds do not start from an equal split (a CPU
// next to a GPU would hold half the particles for the first steps). Fills each slab's calibration
// and hands the fitted models to the balancer; leaves the slabs' particles undefined (the first
// upload comes after).
#pragma once
#include "balance/balancer.hpp"
#include "multi/partition.hpp"
#include "multi/slab.hpp"

#include <vector>

namespace clsph::multi {

void calibrate(std::vector<Slab>& slabs, const Partition& partition, const Particles& particles, const Census& census,
               balance::Balancer& balancer);

}  // namespace clsph::multi
