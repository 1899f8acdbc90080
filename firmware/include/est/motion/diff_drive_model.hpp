#pragma once
// Differential-drive motion model from wheel encoder ticks (or wheel speeds), with noise per wheel.
//
// Pose (x, y, theta): the midpoint of the wheel axle and the heading. Each wheel turns at a constant rate over the
// step, so the axle midpoint moves on a circular arc (est/motion/circular_arc.hpp) of length s = (d_l + d_r) / 2
// while the heading changes by (d_r - d_l) / b, with d_l, d_r the wheels' travelled distances and b the track width:
//   x' = x + s sinc(h) cos(theta + h),  y' = y + s sinc(h) sin(theta + h),  theta' = theta + 2h (+ gamma),
//   h = (d_r - d_l) / (2 b).
// Exact for constant wheel rates; no division by the turn, so straight driving needs no special case.
// Noise: each wheel's travel gets N(0, sigma_w^2) with sigma_w = k |d_w| + sigma_floor (slip grows with distance;
// the floor covers encoder quantisation and creep of a wheel held still), and a small final rotation
// gamma ~ N(0, sigma_g^2) gives the pose a density in all three dimensions.
//
// likelihood() is exact and normalized per (m^2 rad): (x', y') fixes the arc (h from the chord's direction, s from
// its length) up to whole turns, hence (d_l, d_r) = (s - b h, s + b h); the density is the product of the noise
// densities divided by the determinant |d(x', y', theta') / d(d_l, d_r, gamma)| = |chord| |sinc h| / (2 b), summed
// over the turns m = -2..2 (arcs of more than 2.5 turns in one step are neglected). Singular point: the start
// (spinning in place ends there for every turn); integrable, the chord is floored at kDiffDriveMinChord where the
// commanded turn stands in, and every log density is clamped (est/motion/motion_density.hpp): never NaN or inf.
//
// EKF: G = dg/dx_prev, V = dg/d(d_l, d_r), M = diag(sigma_l^2, sigma_r^2); DiffDriveMotionModel, whose control is
// ticks, gives V per tick and M in ticks^2. The final rotation is not a control: an EKF adds sigma_g^2 itself.
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

// Encoder tick deltas over the step, unwrapped by the caller (int32 difference of the raw counters).
struct DiffDriveControl {
  std::int32_t left_ticks = 0;
  std::int32_t right_ticks = 0;

  // A step of more than 2^24 ticks is not exact in float: rejected (rejected_range) as an encoder fault.
  static constexpr std::int32_t kMaxTicks = 16777216;
};

// Distances travelled by the wheels over the step, m.
struct WheelTravel {
  float left = 0.0f;
  float right = 0.0f;

  static constexpr float kMaxTravel = 1.0e4f;  // |d| above this (m) is rejected
};

struct DiffDriveParams {
  float wheel_radius = 0.05f;           // m
  float track_width = 0.3f;             // b: distance between the wheels' contact points, m
  std::uint32_t ticks_per_rev = 4096u;  // encoder ticks per wheel revolution
  float travel_sigma_per_m = 0.0f;      // k: travel std per metre travelled, dimensionless
  float travel_sigma_floor = 0.0f;      // sigma_floor, m
  float final_rot_sigma = 0.0f;         // sigma_g of the final rotation, rad

  static constexpr float kMaxLength = 1.0e3f;  // wheel radius and track width at most this, m
  static constexpr float kMaxNoise = 1.0e6f;   // each noise parameter in [0, kMaxNoise]
};

// Below this chord length (m) the end point is taken to be on top of the start point.
inline constexpr float kDiffDriveMinChord = 1.0e-6f;

inline float diff_drive_m_per_tick(const DiffDriveParams& p) {
  return kTwoPi * p.wheel_radius / static_cast<float>(p.ticks_per_rev);
}

inline WheelTravel wheel_travel_from_ticks(const DiffDriveControl& u, const DiffDriveParams& p) {
  const float m_per_tick = diff_drive_m_per_tick(p);
  return {static_cast<float>(u.left_ticks) * m_per_tick, static_cast<float>(u.right_ticks) * m_per_tick};
}

// For a drive commanded or measured in wheel angular rates (rad/s) instead of ticks.
inline WheelTravel wheel_travel_from_speeds(float left_rad_s, float right_rad_s, float dt, const DiffDriveParams& p) {
  return {left_rad_s * p.wheel_radius * dt, right_rad_s * p.wheel_radius * dt};
}

inline MotionStatus check_diff_drive_params(const DiffDriveParams& p) {
  const float all[] = {p.wheel_radius, p.track_width, p.travel_sigma_per_m, p.travel_sigma_floor, p.final_rot_sigma};
  for (float f : all)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  if (!(p.wheel_radius > 0.0f && p.wheel_radius <= DiffDriveParams::kMaxLength)) return MotionStatus::rejected_range;
  if (!(p.track_width > 0.0f && p.track_width <= DiffDriveParams::kMaxLength)) return MotionStatus::rejected_range;
  if (p.ticks_per_rev == 0u) return MotionStatus::rejected_range;
  const float noise[] = {p.travel_sigma_per_m, p.travel_sigma_floor, p.final_rot_sigma};
  for (float n : noise)
    if (!(n >= 0.0f && n <= DiffDriveParams::kMaxNoise)) return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// Input validation of a travel: non-finite first, then the parameters' ranges, then |d| <= kMaxTravel.
inline MotionStatus check_motion_diff_drive(const WheelTravel& d, const DiffDriveParams& p) {
  if (!fmath::isfinite(d.left) || !fmath::isfinite(d.right)) return MotionStatus::rejected_nonfinite;
  const MotionStatus ps = check_diff_drive_params(p);
  if (ps != MotionStatus::ok) return ps;
  if (fmath::abs(d.left) > WheelTravel::kMaxTravel || fmath::abs(d.right) > WheelTravel::kMaxTravel)
    return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// Input validation of tick deltas: the parameters, then |ticks| <= kMaxTicks and the travel they make.
inline MotionStatus check_motion_diff_drive(const DiffDriveControl& u, const DiffDriveParams& p) {
  const MotionStatus ps = check_diff_drive_params(p);
  if (ps != MotionStatus::ok) return ps;
  const std::int32_t lim = DiffDriveControl::kMaxTicks;
  if (u.left_ticks > lim || u.left_ticks < -lim || u.right_ticks > lim || u.right_ticks < -lim)
    return MotionStatus::rejected_range;
  return check_motion_diff_drive(wheel_travel_from_ticks(u, p), p);
}

namespace diff_drive_detail {

inline Pose2 diff_drive_arc(const Pose2& x, float left, float right, float b) {
  const float s = 0.5f * (left + right);
  const float h = 0.5f * (right - left) / b;
  const float chord = s * arc::sinc(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x.theta + h, sn, cs);
  return {x.x + chord * cs, x.y + chord * sn, fmath::normalize_angle(x.theta + 2.0f * h)};
}

inline float travel_sigma(float d, const DiffDriveParams& p) {
  return p.travel_sigma_per_m * fmath::abs(d) + p.travel_sigma_floor;
}

}  // namespace diff_drive_detail

// Noise-free g(d, x_prev). An unusable input leaves the pose unchanged.
inline Pose2 predict_motion_diff_drive(const Pose2& x_prev, const WheelTravel& d, const DiffDriveParams& p) {
  if (!usable(check_motion_diff_drive(d, p))) return x_prev;
  return diff_drive_detail::diff_drive_arc(x_prev, d.left, d.right, p.track_width);
}

// x ~ p(x | d, x_prev): perturb each wheel's travel, then move exactly. Draws left, right and final rotation noise
// in that order (two draws each). An unusable input leaves the pose unchanged and draws nothing.
inline Pose2 sample_motion_model_diff_drive(const WheelTravel& d, const Pose2& x_prev, const DiffDriveParams& p,
                                            Rng& rng) {
  if (!usable(check_motion_diff_drive(d, p))) return x_prev;
  const float left = d.left + sample_normal(rng, diff_drive_detail::travel_sigma(d.left, p));
  const float right = d.right + sample_normal(rng, diff_drive_detail::travel_sigma(d.right, p));
  const float gamma = sample_normal(rng, p.final_rot_sigma);
  Pose2 out = diff_drive_detail::diff_drive_arc(x_prev, left, right, p.track_width);
  out.theta = fmath::normalize_angle(out.theta + gamma);
  return out;
}

// log p(x | d, x_prev) per (m^2 rad), see the header comment; kLogZero for an unusable input or a non-finite pose.
inline float log_motion_model_diff_drive(const Pose2& x, const WheelTravel& d, const Pose2& x_prev,
                                         const DiffDriveParams& p) {
  if (!usable(check_motion_diff_drive(d, p)) || !x.is_finite() || !x_prev.is_finite())
    return motion_density::kLogZero;
  const float b = p.track_width;
  const float sigma_l = diff_drive_detail::travel_sigma(d.left, p);
  const float sigma_r = diff_drive_detail::travel_sigma(d.right, p);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta, sn, cs);
  const float wx = x.x - x_prev.x;
  const float wy = x.y - x_prev.y;
  const float cx = cs * wx + sn * wy;  // the chord in the start frame
  const float cy = cs * wy - sn * wx;
  const float chord = fmath::sqrt(cx * cx + cy * cy);
  const bool on_start = !(chord >= kDiffDriveMinChord);
  const float log_chord_2b = fmath::log(on_start ? kDiffDriveMinChord : chord) - fmath::log(2.0f * b);
  float sum = motion_density::kLogZero;
  float h0 = 0.0f;
  for (std::int32_t m = on_start ? 0 : -2; m <= (on_start ? 0 : 2); ++m) {
    // On the start point: no translation, and the commanded turn stands in.
    arc::ArcPreimage pre{0.0f, 0.5f * (d.right - d.left) / b, true};
    if (!on_start) pre = arc::arc_preimage(cx, cy, m);
    if (m == 0) h0 = pre.h;
    if (!pre.ok) continue;
    const float sc = fmath::abs(arc::sinc(pre.h));
    if (!(sc > 0.0f)) continue;
    const float term = motion_density::log_prob_normal(pre.s - b * pre.h - d.left, sigma_l) +
                       motion_density::log_prob_normal(pre.s + b * pre.h - d.right, sigma_r) - log_chord_2b -
                       fmath::log(sc);
    sum = motion_density::log_add(sum, motion_density::clamp_log_density(term));
  }
  const float gamma = fmath::normalize_angle(x.theta - x_prev.theta - 2.0f * h0);
  const float total = sum + motion_density::log_prob_normal(gamma, p.final_rot_sigma);
  return motion_density::clamp_log_density(sum <= motion_density::kLogZero ? motion_density::kLogZero : total);
}

// p(x | d, x_prev) per (m^2 rad): the normalized density (see the header comment).
inline float motion_model_diff_drive(const Pose2& x, const WheelTravel& d, const Pose2& x_prev,
                                     const DiffDriveParams& p) {
  return motion_density::density_from_log(log_motion_model_diff_drive(x, d, x_prev, p));
}

// G = dg/dx_prev, V = dg/d(d_l, d_r) per metre, M = diag(sigma_l^2, sigma_r^2) in m^2. With chord c = s sinc(h)
// along psi = theta + h: d/ds moves along the chord, d/dh stretches it (s sinc') and turns it (c), and
// ds/dd_w = 1/2, dh/dd_w = -+1/(2b). Identity and zeros for unusable input.
inline MotionJacobians<3, 2> jacobians_motion_diff_drive(const Pose2& x_prev, const WheelTravel& d,
                                                         const DiffDriveParams& p) {
  MotionJacobians<3, 2> j;
  j.G.setIdentity();
  j.V.setZero();
  j.M.setZero();
  if (!usable(check_motion_diff_drive(d, p))) return j;
  const float b = p.track_width;
  const float s = 0.5f * (d.left + d.right);
  const float h = 0.5f * (d.right - d.left) / b;
  const float sc = arc::sinc(h);
  const float dsc = arc::sinc_derivative(h);
  float sn = 0.0f;
  float cs = 0.0f;
  fmath::sincos(x_prev.theta + h, sn, cs);
  const float chord = s * sc;
  j.G(0, 2) = -chord * sn;
  j.G(1, 2) = chord * cs;
  const float ax = 0.5f * sc * cs;
  const float ay = 0.5f * sc * sn;
  const float bx = (s * dsc * cs - chord * sn) / (2.0f * b);
  const float by = (s * dsc * sn + chord * cs) / (2.0f * b);
  j.V(0, 0) = ax - bx;
  j.V(1, 0) = ay - by;
  j.V(2, 0) = -1.0f / b;
  j.V(0, 1) = ax + bx;
  j.V(1, 1) = ay + by;
  j.V(2, 1) = 1.0f / b;
  const float sl = diff_drive_detail::travel_sigma(d.left, p);
  const float sr = diff_drive_detail::travel_sigma(d.right, p);
  j.M(0, 0) = sl * sl;
  j.M(1, 1) = sr * sr;
  return j;
}

// The differential-drive model in the shape of est/motion/motion_model.hpp, with encoder tick deltas as the control
// (V per tick, M in ticks^2). The free functions above take wheel travel, from ticks or from wheel speeds.
struct DiffDriveMotionModel {
  using State = Pose2;
  using Control = DiffDriveControl;
  using Params = DiffDriveParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 2;  // (left ticks, right ticks)

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_diff_drive(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    if (!usable(check(u, p))) return x_prev;
    return predict_motion_diff_drive(x_prev, wheel_travel_from_ticks(u, p), p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    if (!usable(check(u, p))) return x_prev;
    return sample_motion_model_diff_drive(wheel_travel_from_ticks(u, p), x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_density::density_from_log(log_likelihood(x, u, x_prev, p));
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    if (!usable(check(u, p))) return motion_density::kLogZero;
    return log_motion_model_diff_drive(x, wheel_travel_from_ticks(u, p), x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    MotionJacobians<kStateDim, kControlDim> j;
    j.G.setIdentity();
    j.V.setZero();
    j.M.setZero();
    if (!usable(check(u, p))) return j;
    j = jacobians_motion_diff_drive(x_prev, wheel_travel_from_ticks(u, p), p);
    const float m_per_tick = diff_drive_m_per_tick(p);
    j.V *= m_per_tick;
    j.M /= m_per_tick * m_per_tick;
    return j;
  }
};

}  // namespace est
