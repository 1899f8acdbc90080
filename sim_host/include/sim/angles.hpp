#pragma once
// The simulator's angles: pi and degrees per radian in double, a heading difference wrapped to [-pi, pi].
#include <cmath>

#include "est/math/fmath.hpp"

namespace sim {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegPerRad = 180.0 / kPi;

// The angle a - 2 pi k nearest zero, in [-pi, pi].
inline float wrap_angle(float a) { return std::remainder(a, est::kTwoPi); }

}  // namespace sim
