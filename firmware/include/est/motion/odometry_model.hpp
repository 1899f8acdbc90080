#pragma once
// Odometry motion model (Thrun ch. 5.4): the control is the pair of odometry poses (x_bar_{t-1}, x_bar_t), read as
// a rotation rot1, a straight translation trans and a second rotation rot2 (table 5.5, lines 2-4), each perturbed:
//   var(rot1 noise) = a1 rot1^2 + a2 trans^2,   var(trans noise) = a3 trans^2 + a4 (rot1^2 + rot2^2),
//   var(rot2 noise) = a1 rot2^2 + a2 trans^2,
// the book's parametrization (tables 5.5 and 5.6 pass VARIANCES to prob and sample); zero-mean normal noise.
//
// Reverse motion: lines 2-4 read every translation as a forward one, so a robot that backs up straight has
// rot1 = atan2(dy, dx) - theta ~ pi and rot2 ~ -pi, and a1 pi^2 of noise on each scatters its heading around the
// circle although it never turned (MCL lost the Intel Research Lab robot that way). When |rot1| > pi/2 the
// increment is read as the robot's own motion: trans < 0, rot1 and rot2 shifted by pi (rot1 into [-pi/2, pi/2]),
// which reaches the same pose with the same turn rot1 + rot2, and the noise is that of the small rotations the robot
// made; a chord straight sideways (|rot1| = pi/2) reads the same either way. The sign is all the rest of the model
// sees: g, G and V below hold for a signed trans, the variances use trans^2, and the density already sums both
// preimages. A forward increment is read as before, to the bit.
//
// Pure rotation: when the odometry translation is below Params::min_translation the direction atan2(dy, dx) is
// odometry noise, and rot1 would be anything in [-pi/2, pi/2] (with a1 rot1^2 of noise to match). Then
// rot1 = rot2 = (theta_bar_t - theta_bar_{t-1}) / 2 is used: the limit of a constant-curvature arc as its length goes
// to zero, since an arc's chord leaves at half the turn. The (tiny) translation is kept. A stationary robot (both
// zero) has zero noise: the model then is a point mass at x_prev.
//
// likelihood() is the normalized density p(x' | u, x) per (m^2 rad). Table 5.5 multiplies p1 p2 p3, a density over
// (rot1_hat, trans_hat, rot2_hat); the map to (x', y', theta') is polar in (trans_hat, theta + rot1_hat) with
// theta' = theta + rot1_hat + rot2_hat, so its determinant is |trans_hat| and the density over the pose is
// p1 p2 p3 / rho with rho = |(x', y') - (x, y)|. Two corrections to the table make it the density the sampler
// draws from: trans_hat has either sign (the increment's own when reversing, or noise larger than the translation),
// so each pose has two preimages, (psi - theta, rho, ...) and (psi - theta + pi, -rho, ...), whose terms are added;
// and every angle difference is wrapped to (-pi, pi] (the nearest winding; exact unless rotation noise reaches
// order pi). Singular point: rho -> 0 (x' on top of x); the 1/rho singularity is integrable and rho is floored at
// kOdometryMinChord (1e-6 m), where the commanded rot1 is taken as the chord direction. Every log density is clamped to
// [kLogZero, kMaxLogDensity] (est/motion/motion_density.hpp): never NaN or inf. The book's product is kept as
// motion_model_odometry_unnormalized.
//
// EKF: the control of the Jacobians is the increment (rot1, trans, rot2) (kControlDim = 3), G = dg/dx_prev,
// V = dg/d(rot1, trans, rot2), M = diag of the three variances above.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/motion_density.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// Two consecutive odometry poses, in the odometry's own frame (which may drift against the world).
struct OdometryControl {
  Pose2 odom_prev;  // x_bar_{t-1}
  Pose2 odom;       // x_bar_t

  static constexpr float kMaxCoordinate = 1.0e7f;  // |x|, |y| above this (m) is rejected: float has 1 m steps there
};

struct OdometryParams {
  float a1 = 0.0f;  // rotation noise per rotation (rad^2 / rad^2)
  float a2 = 0.0f;  // rotation noise per translation (rad^2 / m^2)
  float a3 = 0.0f;  // translation noise per translation (m^2 / m^2)
  float a4 = 0.0f;  // translation noise per rotation (m^2 / rad^2)
  float min_translation = 1.0e-4f;  // m: below it the motion is a pure rotation (see the header comment)

  static constexpr float kMaxNoise = 1.0e6f;           // each a_i in [0, kMaxNoise]
  static constexpr float kMaxMinTranslation = 1.0f;    // min_translation in [0, 1] m
};

inline constexpr float kOdometryMinChord = 1.0e-6f;  // m

// The odometry increment of table 5.5, lines 2-4 (and table 5.6, lines 2-4), read as the robot's own motion (see
// the header comment).
struct OdometryIncrement {
  float rot1;   // rad, in [-pi/2, pi/2]
  float trans;  // m, negative when the robot backs up
  float rot2;   // rad, in (-pi, pi]
};

inline MotionStatus check_motion_odometry(const OdometryControl& u, const OdometryParams& p) {
  if (!u.odom_prev.is_finite() || !u.odom.is_finite()) return MotionStatus::rejected_nonfinite;
  const float params[] = {p.a1, p.a2, p.a3, p.a4, p.min_translation};
  for (float f : params)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  const float coords[] = {u.odom_prev.x, u.odom_prev.y, u.odom.x, u.odom.y};
  for (float c : coords)
    if (fmath::abs(c) > OdometryControl::kMaxCoordinate) return MotionStatus::rejected_range;
  const float noise[] = {p.a1, p.a2, p.a3, p.a4};
  for (float a : noise)
    if (!(a >= 0.0f && a <= OdometryParams::kMaxNoise)) return MotionStatus::rejected_range;
  if (!(p.min_translation >= 0.0f && p.min_translation <= OdometryParams::kMaxMinTranslation))
    return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// Lines 2-4 of the tables for a chord (dx, dy) of length `chord` seen from heading theta, with the total turn `turn`:
// a chord behind the robot is a reverse translation. Shifting rot1 in (-pi, pi] by pi is exact (Sterbenz) and lands
// in [-pi/2, pi/2].
inline OdometryIncrement odometry_chord_increment(float dx, float dy, float chord, float turn, float theta) {
  float rot1 = fmath::normalize_angle(fmath::atan2(dy, dx) - theta);
  float trans = chord;
  if (rot1 > kHalfPi) {
    rot1 -= kPi;
    trans = -chord;
  } else if (rot1 < -kHalfPi) {
    rot1 += kPi;
    trans = -chord;
  }
  return {rot1, trans, fmath::normalize_angle(turn - rot1)};
}

inline OdometryIncrement odometry_increment(const OdometryControl& u, const OdometryParams& p) {
  const float dx = u.odom.x - u.odom_prev.x;
  const float dy = u.odom.y - u.odom_prev.y;
  const float trans = fmath::sqrt(dx * dx + dy * dy);
  const float turn = fmath::normalize_angle(u.odom.theta - u.odom_prev.theta);
  if (trans < p.min_translation) {
    const float half = 0.5f * turn;
    return {half, trans, turn - half};
  }
  return odometry_chord_increment(dx, dy, trans, turn, u.odom_prev.theta);
}

// Standard deviations of the noise on (rot1, trans, rot2): square roots of the book's variances.
inline OdometryIncrement odometry_noise(const OdometryIncrement& d, const OdometryParams& p) {
  const float r1 = d.rot1 * d.rot1;
  const float t2 = d.trans * d.trans;
  const float r2 = d.rot2 * d.rot2;
  return {fmath::sqrt(p.a1 * r1 + p.a2 * t2), fmath::sqrt(p.a3 * t2 + p.a4 * r1 + p.a4 * r2),
          fmath::sqrt(p.a1 * r2 + p.a2 * t2)};
}

// The pose reached from x by an increment (table 5.6, lines 8-10).
inline Pose2 odometry_apply(const Pose2& x, const OdometryIncrement& d) {
  float s = 0.0f;
  float c = 0.0f;
  fmath::sincos(x.theta + d.rot1, s, c);
  return {x.x + d.trans * c, x.y + d.trans * s, fmath::normalize_angle(x.theta + d.rot1 + d.rot2)};
}

// Noise-free g(u, x_prev).
inline Pose2 predict_motion_odometry(const Pose2& x_prev, const OdometryControl& u, const OdometryParams& p) {
  return odometry_apply(x_prev, odometry_increment(u, p));
}

// Thrun table 5.6: sample_motion_model_odometry. Draws rot1, trans, rot2 noise in that order (two draws each).
inline Pose2 sample_motion_model_odometry(const OdometryControl& u, const Pose2& x_prev, const OdometryParams& p,
                                          Rng& rng) {
  const OdometryIncrement d = odometry_increment(u, p);
  const OdometryIncrement n = odometry_noise(d, p);
  OdometryIncrement hat{};
  hat.rot1 = d.rot1 - sample_normal(rng, n.rot1);
  hat.trans = d.trans - sample_normal(rng, n.trans);
  hat.rot2 = d.rot2 - sample_normal(rng, n.rot2);
  return odometry_apply(x_prev, hat);
}

// log p(x | u, x_prev) per (m^2 rad): table 5.5 with the 1/rho change of variables and both preimages (see the
// header comment). States that are not finite, or too far apart to represent, have density 0 (kLogZero).
inline float log_motion_model_odometry(const Pose2& x, const OdometryControl& u, const Pose2& x_prev,
                                       const OdometryParams& p) {
  using motion_density::log_prob_normal;
  if (!x.is_finite() || !x_prev.is_finite()) return motion_density::kLogZero;
  const OdometryIncrement d = odometry_increment(u, p);
  const OdometryIncrement n = odometry_noise(d, p);
  const float dx = x.x - x_prev.x;
  const float dy = x.y - x_prev.y;
  const float rho = fmath::sqrt(dx * dx + dy * dy);
  const bool on_start = !(rho >= kOdometryMinChord);
  // rot1_hat of the forward preimage, as an offset from the commanded rot1 (wrapped)
  const float e1 = on_start ? 0.0f : fmath::normalize_angle(d.rot1 - (fmath::atan2(dy, dx) - x_prev.theta));
  // rot2_hat = (theta' - theta) - rot1_hat, so its error is the total turn error less e1
  const float turn_err = fmath::normalize_angle(d.rot1 + d.rot2 - (x.theta - x_prev.theta));
  const float e3 = fmath::normalize_angle(turn_err - e1);
  const float forward = log_prob_normal(e1, n.rot1) + log_prob_normal(d.trans - rho, n.trans) +
                        log_prob_normal(e3, n.rot2);
  const float e1b = fmath::normalize_angle(e1 - kPi);
  const float e3b = fmath::normalize_angle(turn_err - e1b);
  const float backward = log_prob_normal(e1b, n.rot1) + log_prob_normal(d.trans + rho, n.trans) +
                         log_prob_normal(e3b, n.rot2);
  const float rho_eff = on_start ? kOdometryMinChord : rho;
  const float l = motion_density::log_add(motion_density::clamp_log_density(forward),
                                          motion_density::clamp_log_density(backward)) -
                  fmath::log(rho_eff);
  return motion_density::clamp_log_density(l);
}

// Thrun table 5.5: motion_model_odometry, normalized: the density p(x | u, x_prev) per (m^2 rad).
inline float motion_model_odometry(const Pose2& x, const OdometryControl& u, const Pose2& x_prev,
                                   const OdometryParams& p) {
  return motion_density::density_from_log(log_motion_model_odometry(x, u, x_prev, p));
}

// Table 5.5 as printed: p1 p2 p3 of one preimage only, a density over (rot1, trans, rot2) (1 / (m rad^2)), not
// over the pose. Lines 5-7 read the pose pair the way lines 2-4 read the odometry (a chord behind x_prev is a reverse
// translation), else a robot backing up would be compared with its own increment shifted by pi. For comparison with
// the book; use motion_model_odometry for filtering.
inline float motion_model_odometry_unnormalized(const Pose2& x, const OdometryControl& u, const Pose2& x_prev,
                                                const OdometryParams& p) {
  using motion_density::log_prob_normal;
  if (!x.is_finite() || !x_prev.is_finite()) return 0.0f;
  const OdometryIncrement d = odometry_increment(u, p);
  const OdometryIncrement n = odometry_noise(d, p);
  const float dx = x.x - x_prev.x;
  const float dy = x.y - x_prev.y;
  const float rho = fmath::sqrt(dx * dx + dy * dy);
  const OdometryIncrement hat =
      odometry_chord_increment(dx, dy, rho, fmath::normalize_angle(x.theta - x_prev.theta), x_prev.theta);
  return motion_density::density_from_log(log_prob_normal(fmath::normalize_angle(d.rot1 - hat.rot1), n.rot1) +
                                          log_prob_normal(d.trans - hat.trans, n.trans) +
                                          log_prob_normal(fmath::normalize_angle(d.rot2 - hat.rot2), n.rot2));
}

// EKF Jacobians at the increment of u (trans signed): G = dg/dx_prev, V = dg/d(rot1, trans, rot2),
// M = diag(variances).
inline MotionJacobians<3, 3> jacobians_motion_odometry(const Pose2& x_prev, const OdometryControl& u,
                                                       const OdometryParams& p) {
  const OdometryIncrement d = odometry_increment(u, p);
  const OdometryIncrement n = odometry_noise(d, p);
  float s = 0.0f;
  float c = 0.0f;
  fmath::sincos(x_prev.theta + d.rot1, s, c);
  MotionJacobians<3, 3> j;
  j.G << 1.0f, 0.0f, -d.trans * s,  //
      0.0f, 1.0f, d.trans * c,      //
      0.0f, 0.0f, 1.0f;
  j.V << -d.trans * s, c, 0.0f,  //
      d.trans * c, s, 0.0f,      //
      1.0f, 0.0f, 1.0f;
  j.M << n.rot1 * n.rot1, 0.0f, 0.0f,  //
      0.0f, n.trans * n.trans, 0.0f,   //
      0.0f, 0.0f, n.rot2 * n.rot2;
  return j;
}

// The odometry model in the shape of est/motion/motion_model.hpp.
struct OdometryMotionModel {
  using State = Pose2;
  using Control = OdometryControl;
  using Params = OdometryParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 3;  // the Jacobians' control is the increment (rot1, trans, rot2)

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_odometry(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_odometry(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_odometry(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_odometry(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_odometry(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    return jacobians_motion_odometry(x_prev, u, p);
  }
};

}  // namespace est
