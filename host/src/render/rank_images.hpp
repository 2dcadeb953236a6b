// Across MPI ranks only images move (docs/mpi.md): each rank draws its own slabs, the others send
// their slabs' images to rank 0, which merges them in slab order as one process merges its
// devices' images, and finishes the picture.
#pragma once
#include "multi/ranks.hpp"
#include "render/renderer.hpp"
#include "render/splat.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace clsph::render {

template <class Image>
using SlabImages = std::vector<std::pair<std::size_t, Image>>;  // (slab, its image), in slab order

// Collective. On rank 0: every rank's `mine`, in rank order (so in slab order); elsewhere empty.
SlabImages<DepthImage> gather_to_rank0(Ranks& ranks, const SlabImages<DepthImage>& mine);
SlabImages<SplatImage> gather_to_rank0(Ranks& ranks, const SlabImages<SplatImage>& mine);

}  // namespace clsph::render
