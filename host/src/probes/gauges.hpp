// What the probes measure (docs/scenes.md, probes), on the host: where each probe samples the
// fluid, and how its samples become one value. The device only sums, per sample point, over the
// fluid particles within the kernel support (kernels/probes.cl): (sum V_j W, sum p_j V_j W). Both
// the synchronous path and the step ahead (sums computed in the queue) go through these, so they
// read the same.
#pragma once
#include "clsph/scene.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace clsph::probes {

// The sample points of every probe of a scene, in order; probe i owns points [first[i], first[i+1]).
struct Points {
    std::vector<Vec3> points;
    std::vector<std::size_t> first;
    double dz = 0;  // the height probes' spacing along z
};

// Per point: (sum V_j W, sum p_j V_j W) over fluid particles j.
using Sums = std::array<float, 2>;

// A sample point reads as having fluid around it (its Shepard-normalised pressure is used) only
// when the fluid fraction there exceeds this: below it the few particles in reach say little.
constexpr float min_fraction = 0.1f;

// A pressure sensor's face: points on the disc of diameter probe.size through probe.point,
// perpendicular to *probe.normal, on a square lattice of spacing min(dp/2, size/4) (never finer
// than size/32, so a huge sensor stays a few hundred points), centre included. A probe without a
// normal is its point alone.
std::vector<Vec3> face_points(const Probe& probe, double dp);

// Every probe's sample points: a height probe's vertical line every dp/2 from the domain's bottom
// to its top; a pressure probe's face (or point).
Points sample_points(const Scene& scene);

// Water height on one line of fluid fractions f[k] at z0 + k dz: walking up from the bottom, the
// first z where f falls from >= 1/2 to < 1/2, linearly interpolated. 0 when the column never
// reaches 1/2 (dry); NaN when it never falls below it again (full to the domain's top).
double water_height(const Sums* line, std::size_t count, double z0, double dz);

// Mean of the Shepard-normalised pressures (sum pVW / sum VW) of the points with fluid around
// them (min_fraction); NaN when none has.
double face_pressure(const Sums* points, std::size_t count);

// Each probe's value from the sums at sample_points(scene): Pa or m, NaN where no fluid is.
std::vector<double> values(const Scene& scene, const Points& points, const std::vector<Sums>& sums);

}  // namespace clsph::probes
