#pragma once
// Log-space densities for the motion models' likelihoods (Thrun table 5.2, prob(a, b^2) for the normal), with the
// floors and caps that keep every result finite: a density is reported in [0, e^kMaxLogDensity], its log in
// [kLogZero, kMaxLogDensity], never NaN or inf, whatever finite inputs (including zero noise) it is given.
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"

namespace est::motion_density {

using est::kLogZero;
// Upper cap of a log density: e^80 = 5.5e34 per (m^2 rad), far above any density a real noise level produces, and
// far below FLT_MAX so that products with a weight stay finite. Reached only at the models' singular points (zero
// noise, or the end pose on top of the start pose where the polar change of variables divides by the chord).
inline constexpr float kMaxLogDensity = 80.0f;
// A zero standard deviation (zero noise, or noise proportional to a zero control) makes the density a point mass;
// it is evaluated with the standard deviation floored here, in the unit of the quantity (m, rad, m/s, rad/s).
inline constexpr float kMinSigma = 1.0e-6f;
// |a / sigma| is clamped here before squaring, so that the exponent stays finite (1e36 < FLT_MAX).
inline constexpr float kMaxStandardScore = 1.0e18f;

// log N(a; 0, sigma^2), sigma floored at kMinSigma.
inline float log_prob_normal(float a, float sigma) {
  const float s = sigma > kMinSigma ? sigma : kMinSigma;
  float z = a / s;
  if (!(z <= kMaxStandardScore)) z = kMaxStandardScore;  // also maps NaN and +inf to the cap
  if (z < -kMaxStandardScore) z = -kMaxStandardScore;
  return -0.5f * z * z - fmath::log(s) - kLogSqrtTwoPi;
}

// A log density clamped into [kLogZero, kMaxLogDensity]; NaN becomes kLogZero.
inline float clamp_log_density(float l) {
  if (!(l >= kLogZero)) return kLogZero;
  return l < kMaxLogDensity ? l : kMaxLogDensity;
}

// exp of a clamped log density; exactly 0 below float's smallest normal.
inline float density_from_log(float l) {
  const float c = clamp_log_density(l);
  return c < -87.0f ? 0.0f : fmath::exp(c);
}

// log(e^a + e^b) of two clamped log densities, without overflow.
inline float log_add(float a, float b) {
  const float hi = a > b ? a : b;
  const float lo = a > b ? b : a;
  if (lo - hi < -87.0f) return hi;
  return hi + fmath::log(1.0f + fmath::exp(lo - hi));
}

}  // namespace est::motion_density
