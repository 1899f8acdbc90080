#pragma once
// Planar pose (x, y, theta): metres and radians, theta kept in (-pi, pi] by the code that produces it; and the
// composition of poses (a (+) b: b given in a's frame, the head-to-tail rule of Smith and Cheeseman).
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
  bool is_identity() const { return x == 0.0f && y == 0.0f && theta == 0.0f; }
};

// a (+) b.
inline Pose2 compose(const Pose2& a, const Pose2& b) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(a.theta, s, c);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, fmath::normalize_angle(a.theta + b.theta)};
}

// (-) a: the pose with a (+) inverse(a) = identity.
inline Pose2 inverse(const Pose2& a) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(a.theta, s, c);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, fmath::normalize_angle(-a.theta)};
}

// b in a's frame: (-) a (+) b.
inline Pose2 between(const Pose2& a, const Pose2& b) { return compose(inverse(a), b); }

}  // namespace est
