#pragma once
// A range finder carried by a steered part (the handlebar of a bicycle, a steered front axle), Probabilistic
// Robotics ch. 6 exercise: the sensor pose in the robot frame depends on the steering angle alpha. When alpha is
// known only as one of M discrete positions alpha_m with probabilities p(alpha_m | x), the measurement model
// marginalizes it (total probability):
//   p(z | x, m) = sum_m p(alpha_m | x) prod_k p(z_k | x, alpha_m, m),
// evaluated in log space with log-sum-exp, since the products underflow float for any real scan.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

inline constexpr std::int32_t kMaxSteeringHypotheses = 16;

struct SteeredMount {
  float pivot_x = 0.0f;  // m, steering axis in the robot frame
  float pivot_y = 0.0f;
  Pose2 sensor_on_part;  // sensor pose in the steered part's frame (at alpha = 0 the part's axes are the robot's)
};

// Sensor pose in the robot frame at steering angle alpha (rad, counter-clockwise): pivot (+) R(alpha) (+) offset.
inline Pose2 steered_sensor_mount(const SteeredMount& m, float alpha) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(alpha, s, c);
  const Pose2& o = m.sensor_on_part;
  return {m.pivot_x + c * o.x - s * o.y, m.pivot_y + s * o.x + c * o.y, fmath::normalize_angle(alpha + o.theta)};
}

// log sum_m p_m exp(scan_log_likelihood(mount_m)) over the M <= kMaxSteeringHypotheses positions with p_m > 0.
// `scan_log_likelihood` is any callable Pose2 mount -> float (one of the range finder models bound to the scan,
// particle and map). Non-finite or non-positive p_m are skipped; if none is left the result is the log of nothing:
// kBeamLogDensityFloor times the largest beam count the caller passes as `beams`.
template <class ScanLogLikelihood>
float marginalize_steering(const SteeredMount& mount, const float* alphas, const float* probs, std::int32_t m_count,
                           std::int32_t beams, const ScanLogLikelihood& scan_log_likelihood) {
  float terms[kMaxSteeringHypotheses];
  if (m_count > kMaxSteeringHypotheses) m_count = kMaxSteeringHypotheses;
  std::int32_t n = 0;
  for (std::int32_t i = 0; i < m_count; ++i) {
    const float p = probs[i];
    if (!fmath::isfinite(p) || !(p > 0.0f) || !fmath::isfinite(alphas[i])) continue;
    terms[n++] = fmath::log(p) + scan_log_likelihood(steered_sensor_mount(mount, alphas[i]));
  }
  return log_sum_exp(terms, n, static_cast<float>(beams) * kBeamLogDensityFloor);
}

// Table 6.1 with the steering marginalized.
template <class Caster>
float steered_beam_range_finder_model(const ScanBeams& z, const Pose2& x, const SteeredMount& mount,
                                      const float* alphas, const float* probs, std::int32_t m_count,
                                      const Caster& caster, const BeamRangeFinderModel& model) {
  return marginalize_steering(mount, alphas, probs, m_count, z.count, [&](const Pose2& sensor_mount) {
    return beam_range_finder_model(z, x, sensor_mount, caster, model);
  });
}

// Table 6.3 with the steering marginalized.
inline float steered_likelihood_field_range_finder_model(const ScanBeams& z, const Pose2& x,
                                                         const SteeredMount& mount, const float* alphas,
                                                         const float* probs, std::int32_t m_count,
                                                         const LikelihoodField& field) {
  return marginalize_steering(mount, alphas, probs, m_count, z.count, [&](const Pose2& sensor_mount) {
    return likelihood_field_range_finder_model(z, x, sensor_mount, field);
  });
}

}  // namespace est
