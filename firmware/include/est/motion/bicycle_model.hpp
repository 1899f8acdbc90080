#pragma once
// Bicycle motion model with the pose at the FRONT wheel (Probabilistic Robotics, ch. 5 exercise on the bicycle).
//
// Pose (x, y, theta): the front wheel's contact point and the frame's heading (rear wheel -> front wheel). Controls,
// constant over dt: the front wheel's speed v along its own heading theta + a, and the steering angle a (left
// positive). The instantaneous centre of rotation (ICR) is where the rear axle line meets the front wheel's normal;
// the front wheel moves on a circle of radius l / sin(a) about it, and the frame turns at v sin(a) / l. In chord
// form (est/motion/circular_arc.hpp) with s = v dt and h = s sin(a) / (2 l):
//   x' = x + s sinc(h) cos(theta + a + h),  y' = y + s sinc(h) sin(theta + a + h),  theta' = theta + 2h (+ gamma)
// which is exact and never divides by sin(a): a -> 0 is the straight line without a special case.
//
// Noise: a_hat = a + N(0, sigma_a^2), v_hat = v + N(0, k |v|), and a small final rotation gamma ~ N(0, sigma_g^2)
// that gives the pose a density in all three dimensions (without it theta' is a function of (x', y')).
//
// Steering limit a_max, the policy (check() reports it):
//  - |a| <= a_max: used as is.
//  - a_max < |a| <= pi/2: clamped to +-a_max, MotionStatus::clamped (the steering stop; the exercise's 85 deg case).
//  - |a| > pi/2: MotionStatus::rejected_range: not a steering angle (most likely degrees passed as radians).
//  - the noisy a_hat may pass the stop too; the stop is modelled by folding it back into [-a_max, a_max] (reflection
//    at the stop). The wheel never turns past the stop, and the overshooting mass lands just inside it rather than
//    as an atom exactly at it, which would leave the pose without a density. Within ~2 sigma_a of the stop the angle
//    is therefore more likely than the unfolded Gaussian says.
//
// likelihood() is exact, and normalized per (m^2 rad): every (x', y') fixes the ICR (on the rear axle line and on the
// perpendicular bisector of the front wheel's chord), hence a = atan(l dy / (|d|^2 / 2 + l dx)) in the start frame,
// then s up to whole turns about the ICR. The density is the product of the noise densities divided by the
// determinant |d(x', y', theta') / d(s, a, gamma)| = |chord| |cos h + sinc(h) s cos(a) / (2 l)| (the change of
// variables that table 5.1 leaves out), summed over the turns m = -2..2 (arcs of more than 2.5 turns are
// neglected). Singular points: the start (v_hat = 0 reaches it for every a) and its mirror through the rear wheel
// (every circle through the start centred on the rear axle line passes there); both are integrable, the chord is
// floored at kBicycleMinChord and every log density clamped (est/motion/motion_density.hpp): never NaN or inf.
//
// EKF (Thrun table 7.2, lines 3-6): G = dg/dx_prev, V = dg/d(v, a) at the clamped steering, M = diag(k |v|,
// sigma_a^2). The final rotation is not a control: an EKF adds sigma_g^2 to the heading's process noise itself.
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

// Commands, constant over the step.
struct BicycleControl {
  float v = 0.0f;      // front wheel speed along its own heading, m/s (negative: backwards)
  float steer = 0.0f;  // steering angle a, rad, left positive

  static constexpr float kMaxSpeed = 100.0f;  // |v| above this is rejected (rejected_range)
};

struct BicycleParams {
  float frame_length = 1.0f;               // l: rear wheel to front wheel, m
  float steer_max = 1.39626340159546366f;  // a_max, rad, in (0, pi/2); default 80 deg
  float steer_sigma = 0.0f;                // sigma_a, rad
  float speed_var_per_speed = 0.0f;        // k in Var(v_hat) = k |v|, m/s
  float final_rot_sigma = 0.0f;            // sigma_g of the final rotation, rad
  float dt = 0.1f;                         // s, the step the control is held for

  static constexpr float kMinDt = 1.0e-6f;     // s
  static constexpr float kMaxDt = 100.0f;      // s
  static constexpr float kMaxNoise = 1.0e6f;   // each noise parameter in [0, kMaxNoise]
  static constexpr float kMaxLength = 1.0e3f;  // m
};

// Below this chord length (m) the end point is taken to be on top of the start point.
inline constexpr float kBicycleMinChord = 1.0e-6f;

namespace bicycle_detail {

inline float clamp_steer(float a, float a_max) { return a > a_max ? a_max : (a < -a_max ? -a_max : a); }

// Folds an angle into [-a_max, a_max] by reflection at both stops (period 4 a_max). floor is exact, hence the same
// bits from every libm.
inline float fold_steer(float a, float a_max) {
  if (a >= -a_max && a <= a_max) return a;
  const float period = 4.0f * a_max;
  float r = a + a_max;
  r -= period * __builtin_floorf(r / period);
  if (!(r < period)) r = 0.0f;
  if (r > 2.0f * a_max) r = period - r;
  return clamp_steer(r - a_max, a_max);
}

// log density of the folded steering angle at a (|a| <= a_max): the Gaussian at a and at its mirror images; images
// more than 6 a_max away are left out (below exp(-18 (a_max / sigma)^2) relative).
inline float log_prob_folded_steer(float a, float a_cmd, float sigma, float a_max) {
  float l = motion_density::kLogZero;
  for (int k = -1; k <= 1; ++k) {
    const float shift = 4.0f * a_max * static_cast<float>(k);
    l = motion_density::log_add(l, motion_density::log_prob_normal(a + shift - a_cmd, sigma));
    l = motion_density::log_add(l, motion_density::log_prob_normal(2.0f * a_max - a + shift - a_cmd, sigma));
  }
  return l;
}

// The arc for arc length s and steering a (chord form above).
inline Pose2 bicycle_arc(const Pose2& x, float s, float a, float l) {
  const float h = 0.5f * s * fmath::sin(a) / l;
  const float chord = s * arc::sinc(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x.theta + a + h, sn, cs);
  return {x.x + chord * cs, x.y + chord * sn, fmath::normalize_angle(x.theta + 2.0f * h)};
}

inline float speed_sigma(float v, const BicycleParams& p) {
  return fmath::sqrt(p.speed_var_per_speed * fmath::abs(v));
}

}  // namespace bicycle_detail

// Input validation: non-finite first, then ranges (dt, l, a_max, noise, |v|), then the steering policy above.
inline MotionStatus check_motion_bicycle(const BicycleControl& u, const BicycleParams& p) {
  const float all[] = {u.v, u.steer, p.frame_length, p.steer_max, p.steer_sigma, p.speed_var_per_speed,
                       p.final_rot_sigma, p.dt};
  for (float f : all)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  if (!(p.dt >= BicycleParams::kMinDt && p.dt <= BicycleParams::kMaxDt)) return MotionStatus::rejected_range;
  if (!(p.frame_length > 0.0f && p.frame_length <= BicycleParams::kMaxLength)) return MotionStatus::rejected_range;
  if (!(p.steer_max > 0.0f && p.steer_max < kHalfPi)) return MotionStatus::rejected_range;
  const float noise[] = {p.steer_sigma, p.speed_var_per_speed, p.final_rot_sigma};
  for (float n : noise)
    if (!(n >= 0.0f && n <= BicycleParams::kMaxNoise)) return MotionStatus::rejected_range;
  if (fmath::abs(u.v) > BicycleControl::kMaxSpeed) return MotionStatus::rejected_range;
  if (fmath::abs(u.steer) > kHalfPi) return MotionStatus::rejected_range;
  if (fmath::abs(u.steer) > p.steer_max) return MotionStatus::clamped;
  return MotionStatus::ok;
}

// Noise-free g(u, x_prev): the front wheel's pose after dt, steering clamped to the stop. An unusable input leaves
// the pose unchanged.
inline Pose2 predict_motion_bicycle(const Pose2& x_prev, const BicycleControl& u, const BicycleParams& p) {
  if (!usable(check_motion_bicycle(u, p))) return x_prev;
  return bicycle_detail::bicycle_arc(x_prev, u.v * p.dt, bicycle_detail::clamp_steer(u.steer, p.steer_max),
                                     p.frame_length);
}

// x ~ p(x | u, x_prev) in the manner of table 5.3: perturb the controls, then move exactly. Draws steering, speed
// and final rotation noise in that order (two draws each). An unusable input leaves the pose unchanged and draws
// nothing.
inline Pose2 sample_motion_model_bicycle(const BicycleControl& u, const Pose2& x_prev, const BicycleParams& p,
                                         Rng& rng) {
  if (!usable(check_motion_bicycle(u, p))) return x_prev;
  const float a_cmd = bicycle_detail::clamp_steer(u.steer, p.steer_max);
  const float a = bicycle_detail::fold_steer(a_cmd + sample_normal(rng, p.steer_sigma), p.steer_max);
  const float v = u.v + sample_normal(rng, bicycle_detail::speed_sigma(u.v, p));
  const float gamma = sample_normal(rng, p.final_rot_sigma);
  Pose2 out = bicycle_detail::bicycle_arc(x_prev, v * p.dt, a, p.frame_length);
  out.theta = fmath::normalize_angle(out.theta + gamma);
  return out;
}

// log p(x | u, x_prev) per (m^2 rad), see the header comment; kLogZero for an unusable input or a non-finite pose.
inline float log_motion_model_bicycle(const Pose2& x, const BicycleControl& u, const Pose2& x_prev,
                                      const BicycleParams& p) {
  if (!usable(check_motion_bicycle(u, p)) || !x.is_finite() || !x_prev.is_finite()) return motion_density::kLogZero;
  const float l = p.frame_length;
  const float a_cmd = bicycle_detail::clamp_steer(u.steer, p.steer_max);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta, sn, cs);
  const float wx = x.x - x_prev.x;
  const float wy = x.y - x_prev.y;
  const float dx = cs * wx + sn * wy;  // the end point in the start frame
  const float dy = cs * wy - sn * wx;
  const float chord = fmath::sqrt(dx * dx + dy * dy);
  const bool on_start = !(chord >= kBicycleMinChord);
  float a = a_cmd;  // on the start point every a ends there: the commanded one stands in
  if (!on_start) {
    // ICR on the rear axle line x = -l and on the chord's bisector: tan(a) = l dy / (|d|^2 / 2 + l dx).
    const float num = l * dy;
    const float den = 0.5f * (dx * dx + dy * dy) + l * dx;
    if (den == 0.0f) return motion_density::kLogZero;  // a = +-90 deg, beyond any stop
    a = den > 0.0f ? fmath::atan2(num, den) : fmath::atan2(-num, -den);
    if (fmath::abs(a) > p.steer_max) return motion_density::kLogZero;
  }
  float sa = 0.0f;
  float ca = 0.0f;
  fmath::sincos(a, sa, ca);
  const float cx = ca * dx + sa * dy;  // the chord in the front wheel's start direction theta + a
  const float cy = ca * dy - sa * dx;
  const float log_chord = fmath::log(on_start ? kBicycleMinChord : chord);
  const float s_mean = u.v * p.dt;
  const float s_sigma = bicycle_detail::speed_sigma(u.v, p) * p.dt;
  float sum = motion_density::kLogZero;
  float h0 = 0.0f;
  for (std::int32_t m = on_start ? 0 : -2; m <= (on_start ? 0 : 2); ++m) {
    arc::ArcPreimage pre{0.0f, 0.0f, true};
    if (!on_start) pre = arc::arc_preimage(cx, cy, m);
    if (m == 0) h0 = pre.h;
    if (!pre.ok) continue;
    const float det = fmath::abs(fmath::cos(pre.h) + arc::sinc(pre.h) * pre.s * ca / (2.0f * l));
    if (!(det > 0.0f)) continue;
    const float term = motion_density::log_prob_normal(pre.s - s_mean, s_sigma) - log_chord - fmath::log(det);
    sum = motion_density::log_add(sum, motion_density::clamp_log_density(term));
  }
  // Whole turns change the heading by 2 pi, so one residual serves every branch.
  const float gamma = fmath::normalize_angle(x.theta - x_prev.theta - 2.0f * h0);
  const float total = sum + bicycle_detail::log_prob_folded_steer(a, a_cmd, p.steer_sigma, p.steer_max) +
                      motion_density::log_prob_normal(gamma, p.final_rot_sigma);
  return motion_density::clamp_log_density(sum <= motion_density::kLogZero ? motion_density::kLogZero : total);
}

// p(x | u, x_prev) per (m^2 rad): the normalized density (see the header comment).
inline float motion_model_bicycle(const Pose2& x, const BicycleControl& u, const Pose2& x_prev,
                                  const BicycleParams& p) {
  return motion_density::density_from_log(log_motion_model_bicycle(x, u, x_prev, p));
}

// Thrun table 7.2, lines 4-6 for the bicycle: G = dg/dx_prev, V = dg/d(v, a), M = diag(k |v|, sigma_a^2).
// With chord c = s sinc(h) along psi = theta + a + h: d/dv stretches the chord (dt sinc + s sinc' dh/dv) and turns
// it (dh/dv), d/da stretches it (s sinc' dh/da) and turns it (1 + dh/da). Identity and zeros for unusable input.
inline MotionJacobians<3, 2> jacobians_motion_bicycle(const Pose2& x_prev, const BicycleControl& u,
                                                      const BicycleParams& p) {
  MotionJacobians<3, 2> j;
  j.G.setIdentity();
  j.V.setZero();
  j.M.setZero();
  if (!usable(check_motion_bicycle(u, p))) return j;
  const float l = p.frame_length;
  const float a = bicycle_detail::clamp_steer(u.steer, p.steer_max);
  const float s = u.v * p.dt;
  float sa = 0.0f;
  float ca = 0.0f;
  fmath::sincos(a, sa, ca);
  const float h = 0.5f * s * sa / l;
  const float sc = arc::sinc(h);
  const float dsc = arc::sinc_derivative(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta + a + h, sn, cs);
  const float chord = s * sc;
  j.G(0, 2) = -chord * sn;
  j.G(1, 2) = chord * cs;
  const float h_v = 0.5f * p.dt * sa / l;
  const float h_a = 0.5f * s * ca / l;
  const float chord_v = p.dt * sc + s * dsc * h_v;
  const float chord_a = s * dsc * h_a;
  const float turn_a = 1.0f + h_a;
  j.V(0, 0) = chord_v * cs - chord * h_v * sn;
  j.V(1, 0) = chord_v * sn + chord * h_v * cs;
  j.V(2, 0) = 2.0f * h_v;
  j.V(0, 1) = chord_a * cs - chord * turn_a * sn;
  j.V(1, 1) = chord_a * sn + chord * turn_a * cs;
  j.V(2, 1) = 2.0f * h_a;
  j.M(0, 0) = p.speed_var_per_speed * fmath::abs(u.v);
  j.M(1, 1) = p.steer_sigma * p.steer_sigma;
  return j;
}

// The bicycle model in the shape of est/motion/motion_model.hpp.
struct BicycleMotionModel {
  using State = Pose2;
  using Control = BicycleControl;
  using Params = BicycleParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 2;  // (v, steer)

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_bicycle(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_bicycle(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_bicycle(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_bicycle(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_bicycle(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    return jacobians_motion_bicycle(x_prev, u, p);
  }
};

}  // namespace est
