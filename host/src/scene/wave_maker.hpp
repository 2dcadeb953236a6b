// Regular waves from a piston or a flap (clsph/scene.hpp, WaveMaker): the linear dispersion
// relation and first-order wave-maker theory (Biesel's transfer functions, as in Dean &
// Dalrymple, "Water Wave Mechanics for Engineers and Scientists", section 6.2), and the one ramped
// segment a wave maker moves its solid by. Pure host code.
#pragma once
#include "clsph/scene.hpp"

#include <string>

namespace clsph::scene {

// kd of the linear dispersion relation w^2 = g k tanh(kd) for w = 2 pi / period (Newton's method
// from Eckart's approximation, to round-off). period, depth, g > 0.
double wave_number_depth(double period, double depth, double g);

// Wave height over stroke H/S of a piston: 2 (cosh 2kd - 1) / (sinh 2kd + 2kd), written so that no
// term overflows for any kd > 0 (deep water: 2; shallow: kd).
double piston_height_ratio(double kd);
// H/S of a flap hinged at height l above the bed (lambda = l / d in [0, 1); S: the stroke at the
// still-water level): 4 sinh kd / (sinh 2kd + 2kd) (sinh kd - (cosh kd - cosh(lambda kd)) / (kd (1 -
// lambda))), which for lambda = 0 is Biesel's 4 sinh kd / (sinh 2kd + 2kd) (kd sinh kd - cosh kd + 1)
// / kd. Derived from H/S = 4 sinh kd / (sinh 2kd + 2kd) k Int_{-d}^{0} f(z) cosh k(d + z) dz with the
// paddle's displacement profile f (1 at the surface, linear to 0 at the hinge, 0 below it).
double flap_height_ratio(double kd, double lambda);

// Fills w.k, w.wavelength and w.stroke from its height, period and depth with |g| of `gravity`,
// and returns the segment that moves the solid: ramped_sine along the direction (piston) or
// ramped_sine_rotation about the hinge line (flap; the axis up x direction, so the top moves along
// +direction first). Errors name `key` ("boundaries.walls[0].motion.wave_maker") and the value:
// a non-positive depth, height or period, a negative ramp, end <= start, a direction that is not
// horizontal, a hinge not below the still-water level, and waves steeper than the breaking limit
// H/L > 0.142 tanh(kd) (Miche) are refused, not clamped.
MotionSegment wave_maker_segment(WaveMaker& w, const Vec3& gravity, const std::string& key);

}  // namespace clsph::scene
