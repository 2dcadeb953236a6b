// Cut schedules for testing::Seams::cut_schedule that the multi-device suites share.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace clsph::test {

// Cuts between D slabs that sweep back and forth, one or two columns a step, leaving a slab with a
// single column or none now and then: particles cross every cut all the time.
inline std::function<std::vector<std::size_t>(std::uint64_t, std::size_t)> sweeping_cuts(std::size_t D) {
    return [D](std::uint64_t step, std::size_t columns) {
        std::vector<std::size_t> c(D + 1, 0);
        c[D] = columns;
        for (std::size_t d = 1; d < D; ++d) {
            const std::size_t phase = (step * (d + 1) + d * columns / D) % (2 * columns);
            c[d] = phase < columns ? phase : 2 * columns - phase;
        }
        std::sort(c.begin(), c.end());
        return c;
    };
}

}  // namespace clsph::test
