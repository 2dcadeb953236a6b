// When kept cell tables are built again (multi/list_schedule.hpp): pure C++, no device.
#include "multi/list_schedule.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

using clsph::multi::ListSchedule;

TEST_SUITE("physics") {
TEST_CASE("list schedule: a build is due once the bound on any move since the last reaches half the buffer") {
    CHECK(!ListSchedule().on());
    CHECK(ListSchedule().due(1e-9, 0, 0));  // no buffer: every step
    ListSchedule s(0.01);                    // half a buffer of 2 cm
    REQUIRE(s.on());
    s.built();
    CHECK(s.builds() == 1);
    // |v| 1 m/s, |a| 100 m/s^2, dt 1 ms: (1 + 0.5 * 100 * 1e-3) * 1e-3 = 1.05 mm a step.
    const double dt = 1e-3, v2 = 1.0, a2 = 1e4;
    int kept = 0;
    while (!s.due(dt, v2, a2)) {
        s.kept(dt, v2, a2);
        ++kept;
    }
    CHECK(kept == 9);  // 9 x 1.05 mm = 9.45 mm; a tenth would reach 10.5
    CHECK(s.age() == 9);
    CHECK(s.moved() == doctest::Approx(9 * 1.05e-3).epsilon(1e-5));
    s.built();
    CHECK(s.age() == 0);
    CHECK(s.moved() == 0);
    CHECK(s.builds() == 2);
    CHECK(!s.due(dt, v2, a2));
    // One fast particle: a move past half the buffer in one step is due at once.
    CHECK(s.due(dt, 15.0 * 15.0, 0));
    // A blown-up step (NaN reductions) is never kept.
    CHECK(s.due(dt, std::numeric_limits<double>::quiet_NaN(), 0));
    CHECK(s.due(dt, std::numeric_limits<double>::infinity(), 0));
}

TEST_CASE("list schedule: the guess of how many more steps keep the tables, for the steps ahead") {
    ListSchedule s(0.01);
    s.built();
    const double dt = 1e-3, v2 = 1.0, a2 = 1e4;  // 1.05 mm a step, as above: 9 steps kept
    CHECK(s.likely_kept(9, dt, v2, a2, 1.0));
    CHECK_FALSE(s.likely_kept(10, dt, v2, a2, 1.0));
    CHECK(s.likely_kept(7, dt, v2, a2, 1.25));        // 7 x 1.3125 mm = 9.2 mm
    CHECK_FALSE(s.likely_kept(8, dt, v2, a2, 1.25));  // 10.5 mm
    for (int k = 0; k < 4; ++k) s.kept(dt, v2, a2);  // 4.2 mm gone
    CHECK(s.likely_kept(4, dt, v2, a2, 1.25));        // + 5.25 mm
    CHECK_FALSE(s.likely_kept(5, dt, v2, a2, 1.25));
    CHECK_FALSE(s.likely_kept(1, dt, std::numeric_limits<double>::quiet_NaN(), 0, 1.25));
    // Never more than due() allows: where due() says build, no step is likely kept.
    while (!s.due(dt, v2, a2)) s.kept(dt, v2, a2);
    CHECK_FALSE(s.likely_kept(1, dt, v2, a2, 1.0));
}
}
