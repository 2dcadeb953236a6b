// What the stage tests (test_stages.cpp, test_stages_probes.cpp) share: the sizes each stage runs
// at and a plain box scene.
#pragma once
#include "clsph/scene.hpp"

#include <cstddef>

namespace stages_test {

// Empty, one, two, odd and larger than a work-group.
inline constexpr std::size_t kSizes[] = {0, 1, 2, 37, 4099};

inline clsph::Scene box_scene(double dp) {
    clsph::Scene s;
    s.physics.dp = dp;
    s.physics.c0 = 20.0;
    s.domain.min = {0, 0, 0};
    s.domain.max = {1, 0.5, 0.5};
    return s;
}

}  // namespace stages_test
