// Before the first step, with several devices and the dynamic balancer: each device is timed on
// samples of the scene, so devices of different speeds do not start from an equal split (a CPU
// next to a GPU would hold half the particles for the first steps). Fills each slab's calibration
// and hands the fitted models to the balancer; leaves the slabs' particles undefined (the first
// upload comes after). Across ranks it times the slabs of this rank (those with a device).
#pragma once
#include "balance/balancer.hpp"
#include "multi/partition.hpp"
#include "multi/ranks.hpp"
#include "multi/slab.hpp"

#include <functional>
#include <vector>

namespace clsph::multi {

// The scene's particles in columns [lo, hi) (the samples), and how many the scene has.
using ColumnSampler = std::function<Particles(std::size_t lo, std::size_t hi)>;

void calibrate(std::vector<Slab>& slabs, const Partition& partition, const ColumnSampler& sample, std::size_t total,
               const Census& census, balance::Balancer& balancer);

// Across ranks, after calibrate() on every rank: every slab's fitted model on every rank (its
// Slab::calibration and the balancer's), so that every rank's balancer makes the same first cuts.
// Collective.
void share_calibrations(std::vector<Slab>& slabs, Ranks& ranks, balance::Balancer& balancer);

}  // namespace clsph::multi
