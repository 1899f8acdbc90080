#pragma once
// Feature-based measurement model with known correspondence, Probabilistic Robotics table 6.4
// (landmark_model_known_correspondence), its measurement sampler, the pose sampler of table 6.5, and the closed-form
// pose from two identified landmarks (to seed global localization).
//
// A measurement f = (r, phi, s): range (m), bearing (rad, counter-clockwise from the robot heading), signature;
// the correspondence c is the landmark's index in the map. Range, bearing and signature carry independent zero-mean
// Gaussian noise (eq. 6.40); the Gaussians are not truncated (the range density leaks a little mass below 0 when
// r* < 3 sigma_range), and the bearing error is wrapped to (-pi, pi] before the Gaussian is applied.
// sigma_signature <= 0 means "the map's signatures are not measured" and drops that factor.
// log q is floored at kLandmarkLogDensityFloor (log 1e-30), so it is never -inf or NaN.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

inline constexpr float kLandmarkLogDensityFloor = -69.0775527898f;  // log(1e-30)

struct LandmarkMeasurement {
  float range = 0.0f;      // m
  float bearing = 0.0f;    // rad
  float signature = 0.0f;
};

struct LandmarkNoise {
  float sigma_range = 0.1f;      // m
  float sigma_bearing = 0.05f;   // rad
  float sigma_signature = 0.0f;  // <= 0: signature not used
};

enum class LandmarkStatus : std::uint8_t {
  ok = 0,
  nonfinite,          // a measurement field, noise or pose is NaN or infinite
  bad_correspondence, // c is not an index of the map
  bad_noise,          // sigma_range or sigma_bearing <= 0
  negative_range,     // r < 0
};

inline LandmarkStatus check_landmark_measurement(const LandmarkMeasurement& f, std::int32_t c, const LandmarkMap& m,
                                                 const LandmarkNoise& n) {
  if (!fmath::isfinite(f.range) || !fmath::isfinite(f.bearing) || !fmath::isfinite(f.signature) ||
      !fmath::isfinite(n.sigma_range) || !fmath::isfinite(n.sigma_bearing) || !fmath::isfinite(n.sigma_signature))
    return LandmarkStatus::nonfinite;
  if (!(n.sigma_range > 0.0f) || !(n.sigma_bearing > 0.0f)) return LandmarkStatus::bad_noise;
  if (!m.contains(c)) return LandmarkStatus::bad_correspondence;
  if (f.range < 0.0f) return LandmarkStatus::negative_range;
  return LandmarkStatus::ok;
}

// Noise-free measurement of landmark l from pose x (table 6.4 lines 3-4).
inline LandmarkMeasurement expected_landmark_measurement(const Pose2& x, const Landmark& l) {
  const float dx = l.x - x.x;
  const float dy = l.y - x.y;
  return {fmath::sqrt(dx * dx + dy * dy), fmath::normalize_angle(fmath::atan2(dy, dx) - x.theta), l.signature};
}

// log q of table 6.4. Invalid input (see check_landmark_measurement) gives the floor.
inline float landmark_model_known_correspondence(const LandmarkMeasurement& f, std::int32_t c, const Pose2& x,
                                                 const LandmarkMap& m, const LandmarkNoise& n) {
  if (check_landmark_measurement(f, c, m, n) != LandmarkStatus::ok || !x.is_finite()) return kLandmarkLogDensityFloor;
  const LandmarkMeasurement e = expected_landmark_measurement(x, m[c]);
  const float ur = (f.range - e.range) / n.sigma_range;
  const float ub = fmath::normalize_angle(f.bearing - e.bearing) / n.sigma_bearing;
  float quad = ur * ur + ub * ub;
  float sigma_product = n.sigma_range * n.sigma_bearing;
  float factors = 2.0f;
  if (n.sigma_signature > 0.0f) {
    const float us = (f.signature - e.signature) / n.sigma_signature;
    quad += us * us;
    sigma_product *= n.sigma_signature;
    factors = 3.0f;
  }
  const float log_q = -0.5f * quad - fmath::log(sigma_product) - factors * kLogSqrtTwoPi;
  return log_q > kLandmarkLogDensityFloor ? log_q : kLandmarkLogDensityFloor;
}

// A measurement of landmark l from pose x, drawn from the model of table 6.4 (three normal draws, six uniforms).
inline LandmarkMeasurement sample_landmark_measurement(const Pose2& x, const Landmark& l, const LandmarkNoise& n,
                                                       Rng& rng) {
  const LandmarkMeasurement e = expected_landmark_measurement(x, l);
  LandmarkMeasurement f;
  f.range = e.range + sample_normal(rng, n.sigma_range);
  f.bearing = fmath::normalize_angle(e.bearing + sample_normal(rng, n.sigma_bearing));
  const float ds = sample_normal(rng, n.sigma_signature > 0.0f ? n.sigma_signature : 0.0f);
  f.signature = e.signature + ds;
  return f;
}

// Table 6.5, sample_landmark_model_known_correspondence: a pose drawn from p(x | f, c, m) under a uniform prior,
// for seeding particles from one landmark sighting.
inline Pose2 sample_landmark_model_known_correspondence(const LandmarkMeasurement& f, const Landmark& l,
                                                        const LandmarkNoise& n, Rng& rng) {
  const float gamma = rng.uniform(0.0f, kTwoPi);
  const float r = f.range + sample_normal(rng, n.sigma_range);
  const float phi = f.bearing + sample_normal(rng, n.sigma_bearing);
  float s = 0.0f, c = 0.0f;
  fmath::sincos(gamma, s, c);
  return {l.x + r * c, l.y + r * s, fmath::normalize_angle(gamma - kPi - phi)};
}

enum class TwoLandmarkStatus : std::uint8_t {
  ok = 0,
  nonfinite,
  degenerate_landmarks,    // the two landmarks are closer than min_separation: heading unobservable
  degenerate_measurement,  // the two measured points are closer than min_separation
  inconsistent,            // measured and mapped landmark separations differ by more than max_mismatch
};

struct TwoLandmarkPose {
  Pose2 pose;
  TwoLandmarkStatus status = TwoLandmarkStatus::nonfinite;
  float separation_mismatch = 0.0f;  // m, |measured separation - mapped separation|: a consistency check
};

// The robot pose from range and bearing to two identified landmarks, closed form: the measurements place the
// landmarks at p_i = r_i (cos phi_i, sin phi_i) in the robot frame; the heading rotates p2 - p1 onto l2 - l1, and
// the position is the mean of l_i - R(theta) p_i. Exact for noise-free measurements; with noise, the heading error
// is about sigma_range / separation + sigma_bearing. `pose` is unusable unless status is ok.
inline TwoLandmarkPose pose_from_two_landmarks(const Landmark& l1, const LandmarkMeasurement& f1, const Landmark& l2,
                                               const LandmarkMeasurement& f2, float min_separation = 0.05f,
                                               float max_mismatch = 3.0e38f) {
  TwoLandmarkPose out;
  const float in[8] = {l1.x, l1.y, l2.x, l2.y, f1.range, f1.bearing, f2.range, f2.bearing};
  for (float v : in)
    if (!fmath::isfinite(v)) return out;
  float s1 = 0.0f, c1 = 0.0f, s2 = 0.0f, c2 = 0.0f;
  fmath::sincos(f1.bearing, s1, c1);
  fmath::sincos(f2.bearing, s2, c2);
  const float p1x = f1.range * c1, p1y = f1.range * s1;
  const float p2x = f2.range * c2, p2y = f2.range * s2;
  const float mdx = l2.x - l1.x, mdy = l2.y - l1.y;
  const float pdx = p2x - p1x, pdy = p2y - p1y;
  const float map_sep = fmath::sqrt(mdx * mdx + mdy * mdy);
  const float meas_sep = fmath::sqrt(pdx * pdx + pdy * pdy);
  out.separation_mismatch = fmath::abs(map_sep - meas_sep);
  if (!(map_sep >= min_separation)) {
    out.status = TwoLandmarkStatus::degenerate_landmarks;
    return out;
  }
  if (!(meas_sep >= min_separation)) {
    out.status = TwoLandmarkStatus::degenerate_measurement;
    return out;
  }
  if (out.separation_mismatch > max_mismatch) {
    out.status = TwoLandmarkStatus::inconsistent;
    return out;
  }
  const float theta = fmath::normalize_angle(fmath::atan2(mdy, mdx) - fmath::atan2(pdy, pdx));
  float s = 0.0f, c = 0.0f;
  fmath::sincos(theta, s, c);
  const float x1 = l1.x - (c * p1x - s * p1y), y1 = l1.y - (s * p1x + c * p1y);
  const float x2 = l2.x - (c * p2x - s * p2y), y2 = l2.y - (s * p2x + c * p2y);
  out.pose = {0.5f * (x1 + x2), 0.5f * (y1 + y2), theta};
  out.status = TwoLandmarkStatus::ok;
  return out;
}

}  // namespace est
