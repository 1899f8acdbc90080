#pragma once
// A motion model's State as a column vector for the Gaussian filters: Pose2 as (x, y, theta), the holonomic point
// robot's Eigen::Vector2f as (x, y). The position is always the first two entries; a heading, when the state has
// one, is entry 2 and is kept in (-pi, pi].
#include "est/eigen.hpp"
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"

namespace est {

template <typename State>
struct StateVector;

template <>
struct StateVector<Pose2> {
  static constexpr int kDim = 3;
  static constexpr bool kHasHeading = true;
  using Vector = Eigen::Matrix<float, 3, 1>;
  static Vector to_vector(const Pose2& p) { return Vector(p.x, p.y, p.theta); }
  static Pose2 from_vector(const Vector& v) { return Pose2{v(0), v(1), fmath::normalize_angle(v(2))}; }
};

template <>
struct StateVector<Eigen::Matrix<float, 2, 1>> {
  static constexpr int kDim = 2;
  static constexpr bool kHasHeading = false;
  using Vector = Eigen::Matrix<float, 2, 1>;
  static Vector to_vector(const Vector& p) { return p; }
  static Vector from_vector(const Vector& v) { return v; }
};

}  // namespace est
