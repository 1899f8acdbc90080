#pragma once
// Range-only measurement model: the distance to a known point (a beacon, a radio landmark, another robot) with
// zero-mean Gaussian noise, p(z | x) = N(z; ||t - s||, sigma^2), s the sensor position (robot position (+) the
// mount offset). The Gaussian is not truncated at 0 (stated: for true ranges under 3 sigma a little mass lies below
// 0). The log density is floored at kRangeOnlyLogDensityFloor (log 1e-30); invalid input gives the floor.
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

inline constexpr float kRangeOnlyLogDensityFloor = -69.0775527898f;  // log(1e-30)

// Sensor position: robot pose (+) (offset_x, offset_y) in the robot frame.
inline float expected_range(const Pose2& x, float target_x, float target_y, float offset_x = 0.0f,
                            float offset_y = 0.0f) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(x.theta, s, c);
  const float dx = target_x - (x.x + c * offset_x - s * offset_y);
  const float dy = target_y - (x.y + s * offset_x + c * offset_y);
  return fmath::sqrt(dx * dx + dy * dy);
}

inline float range_only_model(float z, const Pose2& x, float target_x, float target_y, float sigma,
                              float offset_x = 0.0f, float offset_y = 0.0f) {
  if (!fmath::isfinite(z) || !fmath::isfinite(target_x) || !fmath::isfinite(target_y) || !x.is_finite() ||
      !fmath::isfinite(sigma) || !(sigma > 0.0f))
    return kRangeOnlyLogDensityFloor;
  const float l = log_normal_density(z - expected_range(x, target_x, target_y, offset_x, offset_y), sigma);
  return l > kRangeOnlyLogDensityFloor ? l : kRangeOnlyLogDensityFloor;
}

// Between two robots: the other robot's position is the target (its heading does not matter).
inline float range_only_model(float z, const Pose2& x, const Pose2& other, float sigma) {
  return range_only_model(z, x, other.x, other.y, sigma);
}

inline float sample_range_only_measurement(const Pose2& x, float target_x, float target_y, float sigma, Rng& rng) {
  return expected_range(x, target_x, target_y) + sample_normal(rng, sigma);
}

}  // namespace est
