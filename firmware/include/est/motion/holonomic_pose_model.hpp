#pragma once
// The holonomic point robot (est/motion/holonomic_model.hpp) carrying a heading it does not steer: its x and y
// motions are driven independently in its own frame and it never turns, x_k+1 = x_k + R(theta_k) (B u_k + w_k),
// theta_k+1 = theta_k + e_k. With theta = 0 this is the point robot of the cooperative EKF-SLAM exercise exactly;
// the heading is there because a rangefinder or a landmark sensor on the robot measures in the robot's frame, and
// MCL's particles and the loop's EKF estimate poses. e_k ~ N(0, heading_sigma^2) is an optional slow drift of the
// heading (0: none, the heading is then a constant the filter learns from its measurements).
//
// likelihood() is the exact density per (m^2 rad): the point robot's Gaussian of R(-theta_prev)(x' - x_prev) (a
// rotation: determinant 1) times N(theta' - theta_prev wrapped; 0, heading_sigma^2), with heading_sigma floored at
// motion_density::kMinSigma (a point mass in heading when it is 0) and the log density clamped.
//
// EKF: G = [I, dR/dtheta B u; 0, 1], V = [R B; 0], M = B^-1 Q B^-T (so V M V^T = R Q R^T); the heading drift is not a
// control noise: an EKF adds heading_sigma^2 to the heading's process noise itself (as for the bicycle's final
// rotation).
#include "est/eigen.hpp"
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/holonomic_model.hpp"
#include "est/motion/motion_density.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

struct HolonomicPoseParams {
  HolonomicParams point;      // B (control to displacement in the robot frame) and Q (m^2, in the robot frame)
  float heading_sigma = 0.0f; // rad per step

  static constexpr float kMaxNoise = 1.0e6f;
};

inline MotionStatus check_motion_holonomic_pose(const Eigen::Vector2f& u, const HolonomicPoseParams& p) {
  if (!fmath::isfinite(p.heading_sigma)) return MotionStatus::rejected_nonfinite;
  const MotionStatus s = check_motion_holonomic(u, p.point);
  if (s != MotionStatus::ok) return s;
  if (!(p.heading_sigma >= 0.0f && p.heading_sigma <= HolonomicPoseParams::kMaxNoise)) return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

namespace holonomic_pose_detail {
// R(theta) d.
inline void rotate(float theta, float dx, float dy, float& wx, float& wy) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(theta, s, c);
  wx = c * dx - s * dy;
  wy = s * dx + c * dy;
}
}  // namespace holonomic_pose_detail

inline Pose2 predict_motion_holonomic_pose(const Pose2& x_prev, const Eigen::Vector2f& u, const HolonomicPoseParams& p) {
  const Eigen::Vector2f d = p.point.B * u;
  float wx = 0.0f, wy = 0.0f;
  holonomic_pose_detail::rotate(x_prev.theta, d(0), d(1), wx, wy);
  return {x_prev.x + wx, x_prev.y + wy, x_prev.theta};
}

// The point robot's displacement with its noise, rotated into the world; then the heading drift.
inline Pose2 sample_motion_model_holonomic_pose(const Eigen::Vector2f& u, const Pose2& x_prev,
                                                const HolonomicPoseParams& p, Rng& rng) {
  const Eigen::Vector2f d = sample_motion_model_holonomic(u, Eigen::Vector2f::Zero(), p.point, rng);
  float wx = 0.0f, wy = 0.0f;
  holonomic_pose_detail::rotate(x_prev.theta, d(0), d(1), wx, wy);
  const float theta = p.heading_sigma > 0.0f ? fmath::normalize_angle(x_prev.theta + sample_normal(rng, p.heading_sigma))
                                             : x_prev.theta;
  return {x_prev.x + wx, x_prev.y + wy, theta};
}

inline float log_motion_model_holonomic_pose(const Pose2& x, const Eigen::Vector2f& u, const Pose2& x_prev,
                                             const HolonomicPoseParams& p) {
  if (!x.is_finite() || !x_prev.is_finite()) return motion_density::kLogZero;
  float bx = 0.0f, by = 0.0f;  // the displacement in the start frame
  holonomic_pose_detail::rotate(-x_prev.theta, x.x - x_prev.x, x.y - x_prev.y, bx, by);
  const float position = log_motion_model_holonomic({bx, by}, u, Eigen::Vector2f::Zero(), p.point);
  const float heading =
      motion_density::log_prob_normal(fmath::normalize_angle(x.theta - x_prev.theta), p.heading_sigma);
  return motion_density::clamp_log_density(position + heading);
}

inline float motion_model_holonomic_pose(const Pose2& x, const Eigen::Vector2f& u, const Pose2& x_prev,
                                         const HolonomicPoseParams& p) {
  return motion_density::density_from_log(log_motion_model_holonomic_pose(x, u, x_prev, p));
}

inline MotionJacobians<3, 2> jacobians_motion_holonomic_pose(const Pose2& x_prev, const Eigen::Vector2f& u,
                                                             const HolonomicPoseParams& p) {
  const MotionJacobians<2, 2> point = jacobians_motion_holonomic(p.point);
  float s = 0.0f, c = 0.0f;
  fmath::sincos(x_prev.theta, s, c);
  Eigen::Matrix2f R;
  R << c, -s, s, c;
  const Eigen::Vector2f d = p.point.B * u;
  MotionJacobians<3, 2> j;
  j.G.setIdentity();
  j.G(0, 2) = -s * d(0) - c * d(1);
  j.G(1, 2) = c * d(0) - s * d(1);
  j.V.setZero();
  j.V.topRows<2>() = R * p.point.B;
  j.M = point.M;
  return j;
}

struct HolonomicPoseMotionModel {
  using State = Pose2;
  using Control = Eigen::Vector2f;
  using Params = HolonomicPoseParams;
  static constexpr int kStateDim = 3;
  static constexpr int kControlDim = 2;

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_holonomic_pose(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_holonomic_pose(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_holonomic_pose(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_holonomic_pose(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_holonomic_pose(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p) {
    return jacobians_motion_holonomic_pose(x_prev, u, p);
  }
};

}  // namespace est
