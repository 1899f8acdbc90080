#pragma once
// Planar pose (x, y, theta): metres and radians, theta kept in (-pi, pi] by the code that produces it.
#include "est/eigen.hpp"
#include "est/math/fmath.hpp"

namespace est {

struct Pose2 {
  float x = 0.0f;
  float y = 0.0f;
  float theta = 0.0f;

  Eigen::Vector3f vector() const { return {x, y, theta}; }
  static Pose2 from_vector(const Eigen::Vector3f& v) { return {v(0), v(1), fmath::normalize_angle(v(2))}; }
  bool is_finite() const { return fmath::isfinite(x) && fmath::isfinite(y) && fmath::isfinite(theta); }
};

}  // namespace est
