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

// dam_break_slice at L = 0.146 with walls on three sides, split along x, half the sound speed: the
// multi-device suites' scene.
inline Scene small_dam(double dp) {
    Scene s = dam_break_slice(0.146, dp, 3.0, x_min | x_max | z_min);
    s.physics.coefsound = 10;
    s.domain.split_axis = 0;
    return s;
}

// A closed 0.3 x 0.1 x 0.3 m tank (no periodic axis) at dp 0.01 with support 4 dp (so the grid's
// reach is 2), fluid filling [0, fluid_x] x [0, 0.1] x [0, fluid_top], split along x.
inline Scene small_tank(double fluid_x, double fluid_top) {
    Scene s;
    s.name = "small tank";
    s.physics.dp = 0.01;
    s.physics.hdp = 2.0;
    s.physics.coefsound = 10;
    s.domain.min = {-0.04, -0.04, -0.04};
    s.domain.max = {0.34, 0.14, 0.34};
    s.domain.split_axis = 0;
    BoxWalls w;
    w.min = {0, 0, 0};
    w.max = {0.3, 0.1, 0.3};
    s.walls.push_back(w);
    FluidBlock f;
    f.min = {0, 0, 0};
    f.max = {fluid_x, 0.1, fluid_top};
    s.fluids.push_back(f);
    return s;
}

}  // namespace clsph::test
