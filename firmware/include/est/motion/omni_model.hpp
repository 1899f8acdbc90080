#pragma once
// Omnidirectional motion model: the velocity model (Thrun table 5.3) with a sideways speed added, as the ch. 5
// exercise on holonomic robots asks.
//
// Controls, constant over dt in the robot's frame: forward speed v1, leftward speed v2, yaw rate w. The body
// velocity turns with the body, so the displacement is the integral of R(theta + w t) (v1, v2), which in chord form
// (est/motion/circular_arc.hpp) with h = w dt / 2 is
//   (x', y') = (x, y) + dt sinc(h) R(theta + h) (v1, v2),   theta' = theta + 2h,
// exact, and with no 1/w, so w -> 0 (straight, crab or diagonal motion) needs no special case.
// Noise on each control: std a1|v1| + a2|v2| + a3|w| on v1, a4.. a6 on v2, a7.. a9 on w.
//
// likelihood() is exact: the map (v1, v2, w) -> (x', y', theta') is invertible up to whole turns of theta' (w from
// theta', then (v1, v2) by undoing the rotation and scaling), with Jacobian determinant dt^3 sinc(h)^2; the turns
// k = -2..2 are summed (turning more than 2.5 turns in one step is neglected). No extra final rotation is needed:
// three noisy controls already give a density in three dimensions. A zero noise makes it a point mass: the standard
// deviations are floored at motion_density::kMinSigma and every log density clamped (est/motion/motion_density.hpp):
// never NaN or inf.
//
// EKF (Thrun table 7.2, lines 3-6): G = dg/dx_prev, V = dg/d(v1, v2, w), M = diag of the three control variances.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/circular_arc.hpp"
#include "est/motion/motion_density.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// Commanded body velocities, constant over the step.
struct OmniControl {
  float v1 = 0.0f;  // forward speed, m/s
  float v2 = 0.0f;  // leftward speed, m/s
  float w = 0.0f;   // yaw rate, rad/s, counter-clockwise positive

  static constexpr float kMaxSpeed = 100.0f;     // |v1|, |v2| above this are rejected (rejected_range)
  static constexpr float kMaxTurnRate = 100.0f;  // |w| above this is rejected
};

struct OmniParams {
  // a1..a9 as alpha[0..8]: std(v1) = a1|v1| + a2|v2| + a3|w|, std(v2) = a4.. a6, std(w) = a7.. a9.
  // Units: the std's units over the control's (a3: m/rad, a7: rad/m, the rest dimensionless).
  float alpha[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  float dt = 0.1f;  // s, the step the control is held for

  static constexpr float kMinDt = 1.0e-6f;    // s
  static constexpr float kMaxDt = 100.0f;     // s
  static constexpr float kMaxNoise = 1.0e6f;  // each alpha in [0, kMaxNoise]
};

namespace omni_detail {

struct Sigmas {
  float v1;
  float v2;
  float w;
};

inline Sigmas sigmas(const OmniControl& u, const OmniParams& p) {
  const float a = fmath::abs(u.v1);
  const float b = fmath::abs(u.v2);
  const float c = fmath::abs(u.w);
  return {p.alpha[0] * a + p.alpha[1] * b + p.alpha[2] * c, p.alpha[3] * a + p.alpha[4] * b + p.alpha[5] * c,
          p.alpha[6] * a + p.alpha[7] * b + p.alpha[8] * c};
}

inline Pose2 omni_arc(const Pose2& x, float v1, float v2, float w, float dt) {
  const float h = 0.5f * w * dt;
  const float k = dt * arc::sinc(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x.theta + h, sn, cs);
  return {x.x + k * (cs * v1 - sn * v2), x.y + k * (sn * v1 + cs * v2), fmath::normalize_angle(x.theta + 2.0f * h)};
}

}  // namespace omni_detail


// Input validation: non-finite first, then ranges (dt, alpha, |v1|, |v2|, |w|).
inline MotionStatus check_motion_omni(const OmniControl& u, const OmniParams& p) {
  const float all[] = {u.v1, u.v2, u.w, p.dt};
  for (float f : all)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  for (float a : p.alpha)
    if (!fmath::isfinite(a)) return MotionStatus::rejected_nonfinite;
  if (!(p.dt >= OmniParams::kMinDt && p.dt <= OmniParams::kMaxDt)) return MotionStatus::rejected_range;
  for (float a : p.alpha)
    if (!(a >= 0.0f && a <= OmniParams::kMaxNoise)) return MotionStatus::rejected_range;
  if (fmath::abs(u.v1) > OmniControl::kMaxSpeed || fmath::abs(u.v2) > OmniControl::kMaxSpeed ||
      fmath::abs(u.w) > OmniControl::kMaxTurnRate)
    return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// Noise-free g(u, x_prev). An unusable input leaves the pose unchanged.
inline Pose2 predict_motion_omni(const Pose2& x_prev, const OmniControl& u, const OmniParams& p) {
  if (!usable(check_motion_omni(u, p))) return x_prev;
  return omni_detail::omni_arc(x_prev, u.v1, u.v2, u.w, p.dt);
}

// x ~ p(x | u, x_prev), table 5.3 with the sideways speed: perturb the three controls, then move exactly. Draws v1,
// v2 and w noise in that order (two draws each). An unusable input leaves the pose unchanged and draws nothing.
inline Pose2 sample_motion_model_omni(const OmniControl& u, const Pose2& x_prev, const OmniParams& p, Rng& rng) {
  if (!usable(check_motion_omni(u, p))) return x_prev;
  const omni_detail::Sigmas sg = omni_detail::sigmas(u, p);
  const float v1 = u.v1 + sample_normal(rng, sg.v1);
  const float v2 = u.v2 + sample_normal(rng, sg.v2);
  const float w = u.w + sample_normal(rng, sg.w);
  return omni_detail::omni_arc(x_prev, v1, v2, w, p.dt);
}

// log p(x | u, x_prev) per (m^2 rad), see the header comment; kLogZero for an unusable input or a non-finite pose.
inline float log_motion_model_omni(const Pose2& x, const OmniControl& u, const Pose2& x_prev, const OmniParams& p) {
  if (!usable(check_motion_omni(u, p)) || !x.is_finite() || !x_prev.is_finite()) return motion_density::kLogZero;
  constexpr float kMinSinc = 1.0e-6f;  // sinc vanishes at a whole turn: every (v1, v2) ends on the start there
  const omni_detail::Sigmas sg = omni_detail::sigmas(u, p);
  const float dt = p.dt;
  const float wx = x.x - x_prev.x;
  const float wy = x.y - x_prev.y;
  const float turn = fmath::normalize_angle(x.theta - x_prev.theta);
  const float log_dt3 = 3.0f * fmath::log(dt);
  float sum = motion_density::kLogZero;
  for (int k = -2; k <= 2; ++k) {
    const float h = 0.5f * (turn + kTwoPi * static_cast<float>(k));
    const float sc = arc::sinc(h);
    if (!(fmath::abs(sc) >= kMinSinc)) continue;
    const float scale = dt * sc;
    float sn = 0.0f;
    float cs = 0.0f;
    fmath::sincos(x_prev.theta + h, sn, cs);
    const float v1 = (cs * wx + sn * wy) / scale;
    const float v2 = (cs * wy - sn * wx) / scale;
    const float w = 2.0f * h / dt;
    const float term = motion_density::log_prob_normal(v1 - u.v1, sg.v1) +
                       motion_density::log_prob_normal(v2 - u.v2, sg.v2) +
                       motion_density::log_prob_normal(w - u.w, sg.w) - log_dt3 - 2.0f * fmath::log(fmath::abs(sc));
    sum = motion_density::log_add(sum, motion_density::clamp_log_density(term));
  }
  return motion_density::clamp_log_density(sum);
}

// p(x | u, x_prev) per (m^2 rad): the exact normalized density (see the header comment).
inline float motion_model_omni(const Pose2& x, const OmniControl& u, const Pose2& x_prev, const OmniParams& p) {
  return motion_density::density_from_log(log_motion_model_omni(x, u, x_prev, p));
}

// G = dg/dx_prev, V = dg/d(v1, v2, w), M = diag of the three control variances. With the body velocity turned into
// the world, r = R(theta + h) (v1, v2), the displacement is dt sinc(h) r; dh/dw = dt / 2 stretches it (sinc') and
// turns it (+90 deg). Identity and zeros for unusable input.
inline MotionJacobians<3, 3> jacobians_motion_omni(const Pose2& x_prev, const OmniControl& u, const OmniParams& p) {
  MotionJacobians<3, 3> j;
  j.G.setIdentity();
  j.V.setZero();
  j.M.setZero();
  if (!usable(check_motion_omni(u, p))) return j;
  const float dt = p.dt;
  const float h = 0.5f * u.w * dt;
  const float sc = arc::sinc(h);
  const float dsc = arc::sinc_derivative(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta + h, sn, cs);
  const float rx = cs * u.v1 - sn * u.v2;
  const float ry = sn * u.v1 + cs * u.v2;
  const float k = dt * sc;
  j.G(0, 2) = -k * ry;
  j.G(1, 2) = k * rx;
  j.V(0, 0) = k * cs;
  j.V(1, 0) = k * sn;
  j.V(0, 1) = -k * sn;
  j.V(1, 1) = k * cs;
  const float half_dt2 = 0.5f * dt * dt;
  j.V(0, 2) = half_dt2 * (dsc * rx - sc * ry);
  j.V(1, 2) = half_dt2 * (dsc * ry + sc * rx);
  j.V(2, 2) = dt;
  const omni_detail::Sigmas sg = omni_detail::sigmas(u, p);
  j.M(0, 0) = sg.v1 * sg.v1;
  j.M(1, 1) = sg.v2 * sg.v2;
  j.M(2, 2) = sg.w * sg.w;
  return j;
}

// The omnidirectional model in the shape of est/motion/motion_model.hpp.
struct OmniMotionModel {
  using State = Pose2;
  using Control = OmniControl;
  using Params = OmniParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 3;  // (v1, v2, w)

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_omni(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_omni(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_omni(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_omni(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_omni(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    return jacobians_motion_omni(x_prev, u, p);
  }
};

}  // namespace est
