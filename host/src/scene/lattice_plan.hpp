// The particles of a scene made of lattice pieces (box walls, solid boxes, fluid blocks), described
// per axis so that they can be generated anywhere — on the host (Scene::build_particles) or on each
// device for its own slab (device/generate.hpp) — with the same ids, positions and densities.
//
// Each piece is a product lattice: per axis a list of coordinates. Boundary pieces keep a point
// when one of its coordinates lies in a face's layers (walls: the layers outside a selected face;
// solid boxes: within `layers` of a face; every point of a filled box). Fluid pieces keep every
// point that is not within dp of a boundary particle. Points are ordered piece by piece
// (boundaries first, then fluid), and within a piece by the split axis first (a "plane" is one
// coordinate of the split axis), so a slab's points of one piece have consecutive ids.
//
// Decisions that depend on arithmetic are made here, once, on the host, into per-axis tables:
// the removal of fluid near boundaries is an integer test on coordinates in units of dp / 2^20;
// a particle's density is looked up by the fluid block that sets its hydrostatic pressure and its
// height. A device needs no double precision to reproduce the host's particles exactly.
// Pure host code: no OpenCL.
#pragma once
#include "clsph/particles.hpp"
#include "clsph/scene.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace clsph::scene {

// A point is within dp of a boundary point when the squared distance in these units is below
// kNearLimit (dp (1 - 1e-6), as the host generator's tolerance for lattice round-off).
constexpr int kFixedBits = 20;
extern const std::int64_t kNearLimit;

struct LatticeAxis {
    int axis = 0;                     // x, y or z
    std::vector<double> x;            // coordinates (m), increasing
    std::vector<std::uint8_t> layer;  // boundary pieces: the coordinate is in a face's layers
    std::vector<std::int64_t> q;      // x in units of dp / 2^kFixedBits
    std::size_t size() const { return x.size(); }
};

// Per boundary piece and axis, for a fluid piece's coordinates on that axis: the squared distance
// (fixed point, capped at kNearLimit) to the piece's nearest layer coordinate and nearest
// coordinate. A fluid point is removed when for some boundary piece and some axis a:
// layer[a] + any[b] + any[c] < kNearLimit (the union of the piece's layer slabs).
struct NearTable {
    std::size_t boundary = 0;                        // the boundary piece
    std::array<std::vector<std::int64_t>, 3> layer;  // by loop position
    std::array<std::vector<std::int64_t>, 3> any;
};

struct LatticePiece {
    bool fluid = false;
    std::size_t source = 0;              // index in Scene::walls, solids or fluids
    std::array<LatticeAxis, 3> axis;     // by loop position: 0 the split axis, then the others
    std::vector<std::uint64_t> plane_count;  // points kept per plane (coordinate of loop position 0)
    std::uint64_t first_id = 0;
    std::uint64_t count = 0;

    // Boundary pieces: which fluid block's hydrostatic pressure a point takes, from its x and y
    // coordinates: bit r of beside[pos][i] is set when the r-th block (in the order of `rank`)
    // is within a kernel support of the coordinate; the first set bit wins (rank orders the
    // blocks by the pressure they give, highest first). density[r * nz + iz]: the density for
    // block rank r (r = blocks: none, rho0) at the iz-th z coordinate; pressure alike.
    // Fluid pieces: the first block (scene order) that holds the point: bit b of inside[pos][i];
    // density[b * nz + iz] (b = blocks: none); velocity[b].
    std::array<std::vector<std::uint64_t>, 3> mask;
    std::vector<float> density, pressure;
    std::vector<std::array<float, 3>> velocity;  // fluid pieces, per block (+ none)
    std::vector<NearTable> near;                 // fluid pieces: the boundary pieces near it

    std::size_t points_per_plane() const { return axis[1].size() * axis[2].size(); }
    int pos_of_axis(int a) const;
    // Whether the fluid point (i0, i1, i2) is within dp of a boundary particle.
    bool removed(std::size_t i0, std::size_t i1, std::size_t i2) const;
    // The mask lookup: the first set bit of mask[0][i0] & mask[1][i1] & mask[2][i2] (masks that
    // do not apply are all ones), or `blocks` when none is set.
    std::size_t block_of(std::size_t i0, std::size_t i1, std::size_t i2, std::size_t blocks) const;
};

struct LatticePlan {
    int split_axis = 0;
    std::size_t blocks = 0;              // fluid blocks (density and velocity tables have one more row)
    std::vector<LatticePiece> pieces;    // boundaries first, then fluid; ids in this order
    std::uint64_t boundary_count = 0, fluid_count = 0;
    std::uint64_t count() const { return boundary_count + fluid_count; }

    // Whether a scene can be described so: no meshes, at most 64 fluid blocks.
    static bool supports(const Scene& scene);
    // Throws SceneError as Scene::build_particles would (an empty fluid block, no fluid).
    static LatticePlan make(const Scene& scene);

    // The particles of the planes `keep_plane(piece, plane)` selects, in id order.
    Particles particles(const std::function<bool(const LatticePiece&, std::size_t plane)>& keep_plane,
                        bool boundary_only = false) const;
    Particles particles() const {
        return particles([](const LatticePiece&, std::size_t) { return true; });
    }
};

// The split axis a domain resolves to (the longest axis unless one is chosen), as device::Grid.
int resolved_split_axis(const Domain& domain);

}  // namespace clsph::scene
