#pragma once
// The shape every motion model of Probabilistic Robotics ch. 5 takes here, so that MCL and the EKFs can use any of
// them. A model is a struct with static members only:
//
//   using State, Control, Params;          State is Pose2 (or Eigen::Vector2f for the holonomic point robot)
//   static constexpr int kStateDim, kControlDim;
//   static MotionStatus check(const Control& u, const Params& p);   input validation; the caller counts rejections
//   static State predict(const State& x_prev, const Control& u, const Params& p);            noise-free g(u, x)
//   static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng);   x ~ p(x | u, x_prev)
//   static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p);
//        the density p(x | u, x_prev) over the state space (per m^2 rad), integrating to 1
//   static MotionJacobians<kStateDim, kControlDim> jacobians(const State& x_prev, const Control& u, const Params& p);
//        G = dg/dx, V = dg/du and M, the control-noise covariance, for EKF prediction (Thrun table 7.2, lines 4-6)
//
// Free functions with the book's names (sample_motion_model_velocity, motion_model_velocity, ...) sit beside each
// model and do the work; the struct only gathers them.
#include <cstdint>

#include "est/eigen.hpp"

namespace est {

enum class MotionStatus : std::uint8_t {
  ok = 0,
  clamped,            // a control was outside its limit and was clamped to it (the model's header says which)
  rejected_nonfinite, // a control or parameter was NaN or infinite: do not predict with it
  rejected_range,     // a control or parameter was outside its physical range (e.g. dt <= 0, negative noise)
};

constexpr bool usable(MotionStatus s) { return s == MotionStatus::ok || s == MotionStatus::clamped; }

template <int N, int U>
struct MotionJacobians {
  Eigen::Matrix<float, N, N> G;  // d g / d x_prev
  Eigen::Matrix<float, N, U> V;  // d g / d u
  Eigen::Matrix<float, U, U> M;  // covariance of the control noise at u
};

}  // namespace est
