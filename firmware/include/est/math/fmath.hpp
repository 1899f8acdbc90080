#pragma once
// The firmware's own float math: the same bits on glibc and newlib, because no libm transcendental is called.
// Accuracy (ULP against a long double reference) is stated per function and tested in tests/test_fmath.cpp.
#include <cstdint>

namespace est {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kTwoPi = 6.28318530717958647692f;
inline constexpr float kHalfPi = 1.57079632679489661923f;

namespace fmath {

float sin(float x);
float cos(float x);
void sincos(float x, float& s, float& c);
float atan2(float y, float x);
float exp(float x);
float log(float x);
// Correctly rounded on every target (IEEE 754 requires it of the hardware instruction and of libm).
inline float sqrt(float x) { return __builtin_sqrtf(x); }

// Angle wrapped to (-pi, pi].
float normalize_angle(float a);

inline bool isfinite(float x) { return __builtin_isfinite(x); }
inline float abs(float x) { return __builtin_fabsf(x); }

}  // namespace fmath
}  // namespace est
