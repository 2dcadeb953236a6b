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
    w.max = {tank_l * L, depth - dp, 2.2 * L};  // along the period: its last column one dp before it
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

// Gauges on still water: a periodic slice (16 dp: 4 grid cells) of a tank (walls at x = 0 and
// x = 0.2, the floor at z = 0) with water 0.1 m deep at dp 0.01 (support 4 dp), and a drop (a
// block of 8 x 7 x 6 particles, its top at 0.3 m) held above the middle. Probes, in order: the
// height gauge under the drop, a dry gauge in the left wall, pressure sensors 2 cm across on the
// left wall (depth 0.05 m, normal [1, 0, 0]) and on the right wall (depth 0.04 m, normal
// [-3, 0, 0]: any length), and a point probe at depth 0.05 m mid-tank.
struct GaugeTank {
    static constexpr double dp = 0.01, width = 0.2, slice = 16 * dp, depth = 0.1, drop_top = 0.3;
    static Scene scene() {
        Scene s;
        s.name = "gauge tank";
        s.physics.dp = dp;
        s.physics.coefsound = 10;
        s.domain.min = {-3 * dp, 0, -3 * dp};
        s.domain.max = {width + 3 * dp, slice, 0.4};
        s.domain.periodic = {false, true, false};
        BoxWalls w;
        w.max = {width, slice, 0.4};
        w.faces = x_min | x_max | z_min;
        s.walls.push_back(w);
        FluidBlock water;
        water.max = {width, slice - 0.5 * dp, depth};
        s.fluids.push_back(water);
        FluidBlock drop;
        drop.min = {0.06, 0.05, drop_top - 5 * dp};
        drop.max = {0.13, 0.11, drop_top};
        s.fluids.push_back(drop);
        auto probe = [&](const char* name, Probe::Kind kind, Vec3 point, std::optional<Vec3> normal = {}) {
            Probe p;
            p.name = name;
            p.kind = kind;
            p.point = point;
            p.normal = normal;
            p.size = 0.02;
            s.probes.push_back(p);
        };
        probe("h_under_drop", Probe::Kind::height, {0.1, 0.08, 0});
        probe("h_dry", Probe::Kind::height, {-0.02, 0.08, 0});
        probe("p_left_wall", Probe::Kind::pressure, {0, 0.08, depth - 0.05}, Vec3{1, 0, 0});
        probe("p_right_wall", Probe::Kind::pressure, {width, 0.08, depth - 0.04}, Vec3{-3, 0, 0});
        probe("p_middle", Probe::Kind::pressure, {0.1, 0.08, depth - 0.05});
        return s;
    }
};

// Two probes on the small dams: the pressure near the floor at x = 0.3 ("base") and the water's
// height over the column ("column").
inline void add_dam_probes(Scene& s) {
    Probe p;
    p.name = "base";
    p.point = {0.3, 0.04, 0.02};
    s.probes.push_back(p);
    Probe h;
    h.kind = Probe::Kind::height;
    h.name = "column";
    h.point = {0.05, 0.04, 0};
    s.probes.push_back(h);
}

inline constexpr double kChannelDp = 0.02, kChannelSpeed = 0.5;

// An open channel (tests/device/test_open_boundaries.cpp, tests/mpi): a slab of water in zero
// gravity, periodic across, free above and below, moving at the inlet's speed along the split axis.
// x: the inlet's box [0, 4 dp], the water to 0.4 m, the outlet at the domain's x+ face 0.4;
// y: periodic, 8 dp; z: the water 6 dp deep, free above and below (no gravity).
inline Scene open_channel() {
    Scene s;
    s.name = "open channel";
    s.physics.dp = kChannelDp;
    s.physics.hdp = 1.3;
    s.physics.gravity = {0, 0, 0};
    s.physics.c0 = 10.0;
    s.domain.min = {0, 0, -0.1};
    s.domain.max = {0.4, 8 * kChannelDp, 0.2};
    s.domain.periodic = {false, true, false};
    s.domain.split_axis = 0;
    FluidBlock f;
    f.min = {4 * kChannelDp, 0, 0};
    f.max = {0.4 - 0.5 * kChannelDp, 7.5 * kChannelDp, 5 * kChannelDp};
    f.velocity = {kChannelSpeed, 0, 0};
    s.fluids.push_back(f);
    Inlet in;
    in.min = {0, 0, 0};
    in.max = {4 * kChannelDp, 7.5 * kChannelDp, 5 * kChannelDp};
    in.velocity = {kChannelSpeed, 0, 0};
    s.inlets.push_back(in);
    s.outlets.push_back(Outlet{0, true});
    s.validate();
    return s;
}

}  // namespace clsph::test
