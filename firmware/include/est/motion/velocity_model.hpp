#pragma once
// Velocity motion model (Thrun ch. 5.3): the robot follows a circular arc at commanded translational speed v and
// turn rate w for dt, then turns in place by gamma * dt (the final rotation that makes the model's support 3-D).
//
// Noise, in the book's parametrization (tables 5.1 and 5.3 pass VARIANCES to prob and sample):
//   var(v_hat - v) = a1 v^2 + a2 w^2,   var(w_hat - w) = a3 v^2 + a4 w^2,   var(gamma_hat) = a5 v^2 + a6 w^2,
// so a1, a3, a5 are dimensionless per (m/s)^2 and a2, a4, a6 per (rad/s)^2 of control; zero-mean normal noise.
//
// Straight motion needs no special case: the arc is written in chord form (est/motion/circular_arc.hpp), the end
// point moves v dt sinc(w dt / 2) along the heading turned by w dt / 2, which is Thrun eq. 5.9 multiplied out; sinc
// uses its Taylor series below |w dt / 2| = arc::kSeriesBelow, so w = 0 and w = 1e-7 give the straight-line pose.
//
// likelihood() is the normalized density p(x' | u, x) per (m^2 rad). Table 5.1 multiplies the three noise densities
// p(v - v_hat) p(w - w_hat) p(gamma_hat), a density over (v_hat, w_hat, gamma_hat), not over the pose: it has units
// and does not integrate to 1 over (x', y', theta'). The change of variables divides it by the determinant of the
// forward map (v_hat, w_hat, gamma_hat) -> (x', y', theta'). With h = w_hat dt / 2 and chord rho = v_hat dt sinc(h)
// the map is (rho, psi = theta + h) -> (x', y') (polar, determinant |rho|) after (v, w) -> (rho, psi) (triangular,
// determinant dt sinc(h) * dt / 2), and theta' = theta + w_hat dt + gamma_hat dt adds a factor dt:
//   |det| = dt * |rho| * dt^2 |sinc h| / 2 = |v_hat| dt^4 sinc(h)^2 / 2 = 2 |v_hat| dt^2 sin^2(w_hat dt / 2) / w_hat^2,
// whose straight limit is |v_hat| dt^4 / 2. The book's product is kept as motion_model_velocity_unnormalized.
//
// Inverse (table 5.1, lines 2-7): the book's circle centre (mu, x*, y*, r*) divides by the lateral offset and fails
// for straight motion; here the end point is expressed in the start frame, the chord direction gives h = w_hat dt/2
// and the chord length gives v_hat = rho / (dt sinc h), defined for every finite pair of poses. The chord fixes h
// only up to multiples of pi (one more full turn of the heading, with the chord's sign alternating); the branch
// nearest the commanded turn w dt / 2 is used, so the density is exact unless the turn noise reaches order pi rad
// per step. Likewise gamma_hat is taken with theta' - theta - w_hat dt wrapped to (-pi, pi].
//
// Singular point: v_hat -> 0 (rotation in place, x' on top of x) makes the polar factor 1/rho infinite; the
// singularity is integrable (like 1/r in the plane) and the density is evaluated with rho floored at
// kVelocityMinChord (1e-6 m), where the direction of the chord is meaningless and the commanded w is taken as w_hat.
// Every log density is clamped to [kLogZero, kMaxLogDensity] (est/motion/motion_density.hpp): never NaN or inf.
//
// EKF (Thrun table 7.2, lines 3-6): G = dg/dx_prev and V = dg/d(v, w) of the noise-free arc (gamma = 0), and
// M = diag(a1 v^2 + a2 w^2, a3 v^2 + a4 w^2); all computed in chord form, so also at w = 0 (where table 7.2's
// expressions divide by w).
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

// Commanded velocities, constant over the step.
struct VelocityControl {
  float v = 0.0f;  // m/s, forward positive
  float w = 0.0f;  // rad/s, counter-clockwise positive

  static constexpr float kMaxSpeed = 100.0f;     // |v| above this is rejected (rejected_range)
  static constexpr float kMaxTurnRate = 100.0f;  // |w| above this is rejected
};

struct VelocityParams {
  float a1 = 0.0f, a2 = 0.0f;  // variance of v_hat - v = a1 v^2 + a2 w^2
  float a3 = 0.0f, a4 = 0.0f;  // variance of w_hat - w = a3 v^2 + a4 w^2
  float a5 = 0.0f, a6 = 0.0f;  // variance of gamma_hat = a5 v^2 + a6 w^2
  float dt = 0.1f;             // s, the step the control is held for

  static constexpr float kMinDt = 1.0e-6f;   // s
  static constexpr float kMaxDt = 100.0f;    // s
  static constexpr float kMaxNoise = 1.0e6f;  // each a_i in [0, kMaxNoise]
};

// Below this chord length (m) the end point is taken to be on top of the start point (see the header comment).
inline constexpr float kVelocityMinChord = 1.0e-6f;

// Standard deviations of the three noise terms at control u (the square roots of the book's variances).
struct VelocityNoise {
  float v;
  float w;
  float gamma;
};

inline VelocityNoise velocity_noise(const VelocityControl& u, const VelocityParams& p) {
  const float v2 = u.v * u.v;
  const float w2 = u.w * u.w;
  return {fmath::sqrt(p.a1 * v2 + p.a2 * w2), fmath::sqrt(p.a3 * v2 + p.a4 * w2),
          fmath::sqrt(p.a5 * v2 + p.a6 * w2)};
}

// Input validation: non-finite first, then ranges (dt in [kMinDt, kMaxDt], a_i in [0, kMaxNoise], |v|, |w|).
inline MotionStatus check_motion_velocity(const VelocityControl& u, const VelocityParams& p) {
  const float all[] = {u.v, u.w, p.a1, p.a2, p.a3, p.a4, p.a5, p.a6, p.dt};
  for (float f : all)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  if (!(p.dt >= VelocityParams::kMinDt && p.dt <= VelocityParams::kMaxDt)) return MotionStatus::rejected_range;
  const float noise[] = {p.a1, p.a2, p.a3, p.a4, p.a5, p.a6};
  for (float a : noise)
    if (!(a >= 0.0f && a <= VelocityParams::kMaxNoise)) return MotionStatus::rejected_range;
  if (fmath::abs(u.v) > VelocityControl::kMaxSpeed || fmath::abs(u.w) > VelocityControl::kMaxTurnRate)
    return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// End pose of the arc at speeds (v, w) for dt followed by a turn gamma * dt (Thrun eq. 5.9 in chord form).
inline Pose2 velocity_arc_end(const Pose2& x, float v, float w, float gamma, float dt) {
  const float h = 0.5f * w * dt;
  const float chord = v * dt * arc::sinc(h);
  float s = 0.0f;
  float c = 0.0f;
  fmath::sincos(x.theta + h, s, c);
  return {x.x + chord * c, x.y + chord * s, fmath::normalize_angle(x.theta + w * dt + gamma * dt)};
}

// Noise-free g(u, x_prev) (Thrun table 7.2, line 3).
inline Pose2 predict_motion_velocity(const Pose2& x_prev, const VelocityControl& u, const VelocityParams& p) {
  return velocity_arc_end(x_prev, u.v, u.w, 0.0f, p.dt);
}

// Thrun table 5.3: sample_motion_model_velocity. Draws v, w, gamma noise in that order (two draws each).
inline Pose2 sample_motion_model_velocity(const VelocityControl& u, const Pose2& x_prev, const VelocityParams& p,
                                          Rng& rng) {
  const VelocityNoise n = velocity_noise(u, p);
  const float v_hat = u.v + sample_normal(rng, n.v);
  const float w_hat = u.w + sample_normal(rng, n.w);
  const float gamma_hat = sample_normal(rng, n.gamma);
  return velocity_arc_end(x_prev, v_hat, w_hat, gamma_hat, p.dt);
}

// The controls (v_hat, w_hat, gamma_hat) that take x_prev to x (table 5.1, lines 2-7, in chord form), and the log of
// |det d(x', y', theta') / d(v_hat, w_hat, gamma_hat)| there.
struct VelocityPreimage {
  float v_hat;
  float w_hat;
  float gamma_hat;
  float log_abs_det;
  bool on_start;  // the chord was below kVelocityMinChord: v_hat = 0, w_hat = w, det uses the floored chord
};

inline VelocityPreimage velocity_preimage(const Pose2& x, const VelocityControl& u, const Pose2& x_prev,
                                          const VelocityParams& p) {
  constexpr float kLogHalf = -0.69314718055994530942f;
  constexpr float kMinSinc = 1.0e-6f;  // sinc vanishes at h = k pi, k != 0: no arc of that turn has this chord
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta, sn, cs);
  const float dx = x.x - x_prev.x;
  const float dy = x.y - x_prev.y;
  const float fwd = cs * dx + sn * dy;  // chord in the start frame
  const float lat = cs * dy - sn * dx;
  const float rho = fmath::sqrt(fwd * fwd + lat * lat);
  const float h_cmd = 0.5f * u.w * p.dt;
  float h = h_cmd;
  float chord = 0.0f;
  const bool on_start = !(rho >= kVelocityMinChord);
  if (!on_start) {
    const float h0 = fmath::atan2(lat, fwd);
    // Branch h0 + m pi nearest the commanded half turn; |t| <= 1.6e3 for checked controls.
    float t = (h_cmd - h0) * (1.0f / kPi);
    if (!(t <= 1.0e6f)) t = 1.0e6f;
    if (t < -1.0e6f) t = -1.0e6f;
    const std::int32_t m = static_cast<std::int32_t>(t >= 0.0f ? t + 0.5f : t - 0.5f);
    h = h0 + static_cast<float>(m) * kPi;
    chord = (m & 1) != 0 ? -rho : rho;
  }
  float sc = arc::sinc(h);
  if (fmath::abs(sc) < kMinSinc) sc = sc < 0.0f ? -kMinSinc : kMinSinc;
  VelocityPreimage r{};
  r.on_start = on_start;
  r.v_hat = chord / (p.dt * sc);
  r.w_hat = 2.0f * h / p.dt;
  r.gamma_hat = fmath::normalize_angle(x.theta - x_prev.theta - 2.0f * h) / p.dt;
  const float rho_eff = on_start ? kVelocityMinChord : rho;
  const float log_dt = fmath::log(p.dt);
  r.log_abs_det = 3.0f * log_dt + fmath::log(rho_eff) + fmath::log(fmath::abs(sc)) + kLogHalf;
  return r;
}

// log p(x | u, x_prev) per (m^2 rad): table 5.1 with the change-of-variables term (see the header comment).
// States that are not finite, or too far apart to represent, have density 0 (kLogZero).
inline float log_motion_model_velocity(const Pose2& x, const VelocityControl& u, const Pose2& x_prev,
                                       const VelocityParams& p) {
  if (!x.is_finite() || !x_prev.is_finite()) return motion_density::kLogZero;
  const VelocityPreimage q = velocity_preimage(x, u, x_prev, p);
  const VelocityNoise n = velocity_noise(u, p);
  const float l = motion_density::log_prob_normal(u.v - q.v_hat, n.v) +
                  motion_density::log_prob_normal(u.w - q.w_hat, n.w) +
                  motion_density::log_prob_normal(q.gamma_hat, n.gamma) - q.log_abs_det;
  return motion_density::clamp_log_density(l);
}

// Thrun table 5.1: motion_model_velocity, normalized: the density p(x | u, x_prev) per (m^2 rad).
inline float motion_model_velocity(const Pose2& x, const VelocityControl& u, const Pose2& x_prev,
                                   const VelocityParams& p) {
  return motion_density::density_from_log(log_motion_model_velocity(x, u, x_prev, p));
}

// Table 5.1 as printed: p(v - v_hat) p(w - w_hat) p(gamma_hat), a density over the controls (s^3 / (m rad^2)), not
// over the pose. For comparison with the book; use motion_model_velocity for filtering.
inline float motion_model_velocity_unnormalized(const Pose2& x, const VelocityControl& u, const Pose2& x_prev,
                                                const VelocityParams& p) {
  if (!x.is_finite() || !x_prev.is_finite()) return 0.0f;
  const VelocityPreimage q = velocity_preimage(x, u, x_prev, p);
  const VelocityNoise n = velocity_noise(u, p);
  return motion_density::density_from_log(motion_density::log_prob_normal(u.v - q.v_hat, n.v) +
                                          motion_density::log_prob_normal(u.w - q.w_hat, n.w) +
                                          motion_density::log_prob_normal(q.gamma_hat, n.gamma));
}

// Thrun table 7.2, lines 4-6: G = dg/dx_prev, V = dg/d(v, w), M = diag(a1 v^2 + a2 w^2, a3 v^2 + a4 w^2).
// With h = w dt / 2, chord c = v dt sinc(h), direction psi = theta + h:
//   dx'/dtheta = -c sin psi, dy'/dtheta = c cos psi;  dx'/dv = dt sinc(h) cos psi, dy'/dv = dt sinc(h) sin psi;
//   dx'/dw = (v dt^2 / 2)(sinc'(h) cos psi - sinc(h) sin psi),
//   dy'/dw = (v dt^2 / 2)(sinc'(h) sin psi + sinc(h) cos psi), dtheta'/dw = dt;
// which equal table 7.2's entries for w != 0 and their limits at w = 0.
inline MotionJacobians<3, 2> jacobians_motion_velocity(const Pose2& x_prev, const VelocityControl& u,
                                                       const VelocityParams& p) {
  const float dt = p.dt;
  const float h = 0.5f * u.w * dt;
  const float sc = arc::sinc(h);
  const float dsc = arc::sinc_derivative(h);
  float s = 0.0f;
  float c = 0.0f;
  fmath::sincos(x_prev.theta + h, s, c);
  const float chord = u.v * dt * sc;
  const float half_v_dt2 = 0.5f * u.v * dt * dt;
  MotionJacobians<3, 2> j;
  j.G << 1.0f, 0.0f, -chord * s,  //
      0.0f, 1.0f, chord * c,      //
      0.0f, 0.0f, 1.0f;
  j.V << dt * sc * c, half_v_dt2 * (dsc * c - sc * s),  //
      dt * sc * s, half_v_dt2 * (dsc * s + sc * c),     //
      0.0f, dt;
  const VelocityNoise n = velocity_noise(u, p);
  j.M << n.v * n.v, 0.0f,  //
      0.0f, n.w * n.w;
  return j;
}

// The velocity model in the shape of est/motion/motion_model.hpp.
struct VelocityMotionModel {
  using State = Pose2;
  using Control = VelocityControl;
  using Params = VelocityParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 2;

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_velocity(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_velocity(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_velocity(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_velocity(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_velocity(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    return jacobians_motion_velocity(x_prev, u, p);
  }
};

}  // namespace est
