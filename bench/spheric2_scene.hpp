// The SPHERIC benchmark test 2 (dam break with an obstacle, Kleefsman et al. 2005) built in C++,
// as ../shared/data/spheric2_benchmark_case.md specifies it (scenes/spheric2.json is the same case).
#pragma once
#include "clsph/scene.hpp"

#include <cmath>

namespace clsph::bench {

inline Scene spheric2_scene(double dp) {
    Scene s;
    s.name = "SPHERIC test 2";
    auto& ph = s.physics;
    ph.dp = dp;
    ph.hdp = 2.0;
    ph.kernel = KernelType::wendland_c2;
    ph.alpha = 0.02;
    ph.delta = 0.1;
    ph.diffusion = Diffusion::fourtakas;
    ph.rho0 = 1000.0;
    ph.coefsound = 20.0;  // c0 = 20 sqrt(g 0.55) ~ 46.4 m/s
    ph.cfl = 0.2;
    BoxWalls tank;  // inner faces at the tank's walls, 3 layers outward on all six faces
    tank.min = {0, 0, 0};
    tank.max = {3.22, 1.0, 2.0};
    tank.layers = 3;
    s.walls.push_back(tank);
    SolidBox obstacle;
    obstacle.min = {0.66, 0.30, 0.0};
    obstacle.max = {0.82, 0.70, 0.16};
    obstacle.layers = 3;
    s.solids.push_back(obstacle);
    FluidBlock water;
    water.min = {1.992, 0.0, 0.0};
    water.max = {3.22, 1.0, 0.55};
    s.fluids.push_back(water);
    const double pad = 3 * dp;
    s.domain.min = {-pad, -pad, -pad};
    s.domain.max = {3.22 + pad, 1.0 + pad, 2.0 + pad};
    s.run.end_time = 0.1;
    return s;
}

}  // namespace clsph::bench
