#pragma once
// Holonomic point robot: x_{k+1} = x_k + B u_k + w_k, w_k ~ N(0, Q), the motion model of the cooperative EKF-SLAM
// exercise (a linear-Gaussian model in the sense of Thrun eq. 3.2). The state is the position (m); the control is
// the commanded displacement of the step (m) with B = I (the default), or a velocity (m/s) with B = dt I, or any
// invertible 2x2 map from control to displacement. Q is the 2x2 covariance (m^2) of the displacement noise, symmetric
// positive semi-definite; Q = 0 gives exact kinematics.
//
// likelihood() is the exact Gaussian density N(x - x_prev - B u; 0, Q) per m^2 (it integrates to 1 over the plane).
// A singular Q makes it a point mass on a line or a point: Q's Cholesky factor has its diagonal floored at
// motion_density::kMinSigma (1e-6 m) there, and the log density is clamped to [kLogZero, kMaxLogDensity].
//
// EKF: G = I, V = B, and M = B^-1 Q B^-T, the control-noise covariance with V M V^T = Q, so that the prediction
// Sigma' = G Sigma G^T + V M V^T adds exactly Q (Thrun table 3.1, line 3, with R = Q).
#include "est/eigen.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/motion_density.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

struct HolonomicParams {
  Eigen::Matrix2f B = Eigen::Matrix2f::Identity();  // control to displacement
  Eigen::Matrix2f Q = Eigen::Matrix2f::Zero();      // m^2, covariance of w_k

  static constexpr float kMaxControl = 1.0e6f;  // |u_i| above this is rejected
  // |det B| below kMinDetB * max|B_ij|^2 is rejected as singular: M = B^-1 Q B^-T would not exist.
  static constexpr float kMinDetB = 1.0e-6f;
  // Q is accepted as symmetric if |q12 - q21| <= kSymmetryTol (|q11| + |q22|), as positive semi-definite if
  // q11 q22 - q12 q21 >= -kSymmetryTol q11 q22 (float rounding of a rank-deficient Q).
  static constexpr float kSymmetryTol = 1.0e-5f;
};

// Lower Cholesky factor of Q (l11, l21, l22), from the symmetric part of Q; negative pivots from rounding become 0.
struct HolonomicNoiseFactor {
  float l11;
  float l21;
  float l22;
};

inline HolonomicNoiseFactor holonomic_noise_factor(const HolonomicParams& p) {
  const float q11 = p.Q(0, 0);
  const float q12 = 0.5f * (p.Q(0, 1) + p.Q(1, 0));
  const float q22 = p.Q(1, 1);
  HolonomicNoiseFactor f{0.0f, 0.0f, 0.0f};
  f.l11 = fmath::sqrt(q11 > 0.0f ? q11 : 0.0f);
  f.l21 = f.l11 > 0.0f ? q12 / f.l11 : 0.0f;
  const float pivot = q22 - f.l21 * f.l21;
  f.l22 = fmath::sqrt(pivot > 0.0f ? pivot : 0.0f);
  return f;
}

inline MotionStatus check_motion_holonomic(const Eigen::Vector2f& u, const HolonomicParams& p) {
  const float all[] = {u(0), u(1), p.B(0, 0), p.B(0, 1), p.B(1, 0), p.B(1, 1),
                       p.Q(0, 0), p.Q(0, 1), p.Q(1, 0), p.Q(1, 1)};
  for (float f : all)
    if (!fmath::isfinite(f)) return MotionStatus::rejected_nonfinite;
  if (fmath::abs(u(0)) > HolonomicParams::kMaxControl || fmath::abs(u(1)) > HolonomicParams::kMaxControl)
    return MotionStatus::rejected_range;
  float b_max = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const float b = fmath::abs(p.B(i % 2, i / 2));
    b_max = b > b_max ? b : b_max;
  }
  const float det_b = p.B(0, 0) * p.B(1, 1) - p.B(0, 1) * p.B(1, 0);
  if (!(b_max > 0.0f) || !(fmath::abs(det_b) >= HolonomicParams::kMinDetB * b_max * b_max))
    return MotionStatus::rejected_range;
  const float q11 = p.Q(0, 0);
  const float q22 = p.Q(1, 1);
  if (!(q11 >= 0.0f && q22 >= 0.0f)) return MotionStatus::rejected_range;
  if (fmath::abs(p.Q(0, 1) - p.Q(1, 0)) > HolonomicParams::kSymmetryTol * (q11 + q22))
    return MotionStatus::rejected_range;
  if (q11 * q22 - p.Q(0, 1) * p.Q(1, 0) < -HolonomicParams::kSymmetryTol * q11 * q22)
    return MotionStatus::rejected_range;
  return MotionStatus::ok;
}

// Noise-free g(u, x_prev) = x_prev + B u.
inline Eigen::Vector2f predict_motion_holonomic(const Eigen::Vector2f& x_prev, const Eigen::Vector2f& u,
                                                const HolonomicParams& p) {
  return x_prev + p.B * u;
}

// x ~ N(x_prev + B u, Q), as x_prev + B u + L z with L L^T = Q and z two standard normals (two draws each).
inline Eigen::Vector2f sample_motion_model_holonomic(const Eigen::Vector2f& u, const Eigen::Vector2f& x_prev,
                                                     const HolonomicParams& p, Rng& rng) {
  const HolonomicNoiseFactor f = holonomic_noise_factor(p);
  const float z1 = sample_normal(rng, 1.0f);
  const float z2 = sample_normal(rng, 1.0f);
  const Eigen::Vector2f mean = predict_motion_holonomic(x_prev, u, p);
  return {mean(0) + f.l11 * z1, mean(1) + (f.l21 * z1 + f.l22 * z2)};
}

// log N(x; x_prev + B u, Q) per m^2, with Q's Cholesky diagonal floored at kMinSigma.
inline float log_motion_model_holonomic(const Eigen::Vector2f& x, const Eigen::Vector2f& u,
                                        const Eigen::Vector2f& x_prev, const HolonomicParams& p) {
  using motion_density::kMinSigma;
  if (!fmath::isfinite(x(0)) || !fmath::isfinite(x(1)) || !fmath::isfinite(x_prev(0)) ||
      !fmath::isfinite(x_prev(1)))
    return motion_density::kLogZero;
  HolonomicNoiseFactor f = holonomic_noise_factor(p);
  if (f.l11 < kMinSigma) {
    f.l11 = kMinSigma;
    f.l21 = 0.0f;  // q12 = 0 whenever q11 = 0 in a positive semi-definite Q
  }
  if (f.l22 < kMinSigma) f.l22 = kMinSigma;
  const Eigen::Vector2f mean = predict_motion_holonomic(x_prev, u, p);
  const float r1 = x(0) - mean(0);
  const float r2 = x(1) - mean(1);
  // log N(r; 0, L L^T) = log N(z1; 0, 1) + log N(z2; 0, 1) - log(l11 l22), z = L^-1 r, written as two 1-D normals
  const float z1 = r1 / f.l11;
  const float l = motion_density::log_prob_normal(r1, f.l11) +
                  motion_density::log_prob_normal(r2 - f.l21 * z1, f.l22);
  return motion_density::clamp_log_density(l);
}

// The Gaussian density p(x | u, x_prev) per m^2.
inline float motion_model_holonomic(const Eigen::Vector2f& x, const Eigen::Vector2f& u,
                                    const Eigen::Vector2f& x_prev, const HolonomicParams& p) {
  return motion_density::density_from_log(log_motion_model_holonomic(x, u, x_prev, p));
}

// G = I, V = B, M = B^-1 Q B^-T (see the header comment).
inline MotionJacobians<2, 2> jacobians_motion_holonomic(const HolonomicParams& p) {
  MotionJacobians<2, 2> j;
  j.G.setIdentity();
  j.V = p.B;
  const float det_b = p.B(0, 0) * p.B(1, 1) - p.B(0, 1) * p.B(1, 0);
  Eigen::Matrix2f b_inv;
  b_inv << p.B(1, 1) / det_b, -p.B(0, 1) / det_b,  //
      -p.B(1, 0) / det_b, p.B(0, 0) / det_b;
  j.M = b_inv * p.Q * b_inv.transpose();
  return j;
}

// The holonomic model in the shape of est/motion/motion_model.hpp.
struct HolonomicMotionModel {
  using State = Eigen::Vector2f;
  using Control = Eigen::Vector2f;
  using Params = HolonomicParams;
  static constexpr int kStateDim = 2;
  static constexpr int kControlDim = 2;

  static MotionStatus check(const Control& u, const Params& p) { return check_motion_holonomic(u, p); }
  static State predict(const State& x_prev, const Control& u, const Params& p) {
    return predict_motion_holonomic(x_prev, u, p);
  }
  static State sample(const State& x_prev, const Control& u, const Params& p, Rng& rng) {
    return sample_motion_model_holonomic(u, x_prev, p, rng);
  }
  static float likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return motion_model_holonomic(x, u, x_prev, p);
  }
  static float log_likelihood(const State& x, const Control& u, const State& x_prev, const Params& p) {
    return log_motion_model_holonomic(x, u, x_prev, p);
  }
  static MotionJacobians<kStateDim, kControlDim> jacobians(const State& /*x_prev*/, const Control& /*u*/,
                                                           const Params& p) {
    return jacobians_motion_holonomic(p);
  }
};

}  // namespace est
