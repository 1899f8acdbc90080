#pragma once
// Normal distribution helpers for the sensor models: log-density, CDF (for truncated Gaussians) and log-sum-exp.
#include <cstdint>

#include "est/math/fmath.hpp"

namespace est {

inline constexpr float kLogSqrtTwoPi = 0.91893853320467274178f;  // log(sqrt(2 pi))
// Stands for log 0 in every log-space weight and density of the firmware: exp(kLogZero - anything finite) is 0.
inline constexpr float kLogZero = -1.0e30f;

// log N(a; 0, sigma^2) for sigma > 0, with log(sigma) passed in so per-beam loops need no log call.
inline float log_normal_density(float a, float sigma, float log_sigma) {
  const float z = a / sigma;
  return -0.5f * z * z - log_sigma - kLogSqrtTwoPi;
}
inline float log_normal_density(float a, float sigma) { return log_normal_density(a, sigma, fmath::log(sigma)); }

// Standard normal CDF Phi(z), through erf by Abramowitz and Stegun 7.1.26 (|error of erf| <= 1.5e-7); the lower
// tail is computed without cancellation, so Phi(-10) keeps its relative accuracy (~1e-6). Phi(+-inf) = 1, 0;
// NaN gives 0.5 (never propagates).
inline float normal_cdf(float z) {
  if (!(z == z)) return 0.5f;
  constexpr float kInvSqrt2 = 0.70710678118654752440f;
  const float x = fmath::abs(z) * kInvSqrt2;
  if (x > 9.0f) return z < 0.0f ? 0.0f : 1.0f;  // tail below 1e-36: under float's normal range
  const float t = 1.0f / (1.0f + 0.3275911f * x);
  const float poly =
      t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  const float tail = 0.5f * poly * fmath::exp(-x * x);
  return z < 0.0f ? tail : 1.0f - tail;
}

// log(sum_i exp(a_i)) over n values, stable; entries equal to -inf (or below -1e30) are skipped, and an all-skipped
// input returns `floor`. n is the loop bound.
inline float log_sum_exp(const float* a, std::int32_t n, float floor) {
  float m = -3.0e38f;
  for (std::int32_t i = 0; i < n; ++i)
    if (a[i] > m) m = a[i];
  if (!(m > -1.0e30f)) return floor;
  float s = 0.0f;
  for (std::int32_t i = 0; i < n; ++i)
    if (a[i] > -1.0e30f) s += fmath::exp(a[i] - m);
  return m + fmath::log(s);
}

}  // namespace est
