#include "multi/list_schedule.hpp"

#include <cmath>

namespace clsph::multi {

double ListSchedule::bound(double dt, double max_speed2, double max_accel2) {
    // The reductions are floats: a relative 1e-6 more covers their round-off and the drift's.
    return (std::sqrt(max_speed2) + 0.5 * std::sqrt(max_accel2) * dt) * dt * (1.0 + 1e-6);
}

bool ListSchedule::due(double dt, double max_speed2, double max_accel2) const {
    if (!on()) return true;
    const double next = moved_ + bound(dt, max_speed2, max_accel2);
    return !(next < half_buffer_);  // NaN (a blown-up step): build
}

}  // namespace clsph::multi
