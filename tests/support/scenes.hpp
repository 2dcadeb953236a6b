// Scenes the device test suites share.
#pragma once
#include "clsph/scene.hpp"

namespace clsph::test {

// A 2:1 water column of width L against the wall at x = 0, in a tank tank_l * L long and 2.2 L
// high, as a thin slice periodic in y (8 particles deep: three kernel supports at h = 1.3 dp).
// The fluid fills x in [dp, L]; `faces` says which tank walls exist.
inline Scene dam_break_slice(double L, double dp, double tank_l, unsigned faces) {
    Scene s;
    s.name = "dam break";
    s.physics.dp = dp;
    s.physics.hdp = 1.3;
    const double depth = 8 * dp;
    s.domain.min = {-3 * dp, 0, -3 * dp};
    s.domain.max = {tank_l * L + 3 * dp, depth, 2.2 * L};
    s.domain.periodic = {false, true, false};
    BoxWalls w;
    w.min = {0, 0, 0};
    w.max = {tank_l * L, depth, 2.2 * L};
    w.faces = faces;
    s.walls.push_back(w);
    FluidBlock f;
    f.min = {0, 0, 0};
    f.max = {L, depth - 0.5 * dp, 2 * L};
    s.fluids.push_back(f);
    return s;
}

}  // namespace clsph::test
