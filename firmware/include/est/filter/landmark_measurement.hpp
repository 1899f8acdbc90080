#pragma once
// Measurement functions of the Gaussian filters and their Jacobians: range between two positions (robot-robot and
// range-only robot-landmark, the team exercise), range and bearing of a landmark from a robot (Thrun eq. 7.12-7.14,
// with the Jacobian on the landmark added for EKF-SLAM, table 10.1 line 16), and the inverse, a landmark placed from
// a robot and its range/bearing (table 10.1 lines 9-10) with the Jacobians that carry the covariance into the map.
//
// The robot state has D = 2 (point robot: x, y) or D = 3 (pose: x, y, theta) entries. A point robot has no heading,
// so its bearings are taken in the world frame (a sensor stabilized by a compass); a pose robot's in its own frame.
#include "est/eigen.hpp"
#include "est/math/fmath.hpp"

namespace est {

// Below this separation (m) range and bearing have no usable derivative: such a measurement is refused.
inline constexpr float kMinMeasurementRange = 1.0e-4f;

struct RangeMeasurement {
  float range = 0.0f;              // |b - a|, m
  Eigen::Matrix<float, 1, 2> d_a;  // d range / d a
  Eigen::Matrix<float, 1, 2> d_b;  // d range / d b
  bool ok = false;                 // false when |b - a| < kMinMeasurementRange or not finite
};

// h(a, b) = |b - a| and its gradients (the exercise's range measurement, robot-robot or robot-landmark).
inline RangeMeasurement range_measurement(const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
  RangeMeasurement out;
  const float dx = b(0) - a(0);
  const float dy = b(1) - a(1);
  const float r = fmath::sqrt(dx * dx + dy * dy);
  out.range = r;
  out.ok = fmath::isfinite(r) && r >= kMinMeasurementRange;
  if (!out.ok) {
    out.d_a.setZero();
    out.d_b.setZero();
    return out;
  }
  out.d_b << dx / r, dy / r;
  out.d_a << -dx / r, -dy / r;
  return out;
}

template <int D>
struct RangeBearingMeasurement {
  Eigen::Vector2f z;                   // (range m, bearing rad in (-pi, pi])
  Eigen::Matrix<float, 2, D> H_robot;  // d z / d robot state
  Eigen::Matrix2f H_landmark;          // d z / d landmark position
  bool ok = false;
};

// Predicted range and bearing of landmark m from robot state x (Thrun eq. 7.12-7.14; table 10.1 lines 12-16).
template <int D>
RangeBearingMeasurement<D> range_bearing_measurement(const Eigen::Matrix<float, D, 1>& x, const Eigen::Vector2f& m) {
  static_assert(D == 2 || D == 3, "robot state is (x, y) or (x, y, theta)");
  RangeBearingMeasurement<D> out;
  out.H_robot.setZero();
  out.H_landmark.setZero();
  const float dx = m(0) - x(0);
  const float dy = m(1) - x(1);
  const float q = dx * dx + dy * dy;
  const float r = fmath::sqrt(q);
  out.ok = fmath::isfinite(r) && r >= kMinMeasurementRange;
  if (!out.ok) {
    out.z.setZero();
    return out;
  }
  float bearing = fmath::atan2(dy, dx);
  if constexpr (D == 3) bearing -= x(2);
  out.z << r, fmath::normalize_angle(bearing);
  out.H_landmark << dx / r, dy / r, -dy / q, dx / q;
  out.H_robot(0, 0) = -dx / r;
  out.H_robot(0, 1) = -dy / r;
  out.H_robot(1, 0) = dy / q;
  out.H_robot(1, 1) = -dx / q;
  if constexpr (D == 3) out.H_robot(1, 2) = -1.0f;
  return out;
}

template <int D>
struct LandmarkFromRangeBearing {
  Eigen::Vector2f m;                   // landmark position, m
  Eigen::Matrix<float, 2, D> G_robot;  // d m / d robot state
  Eigen::Matrix2f G_z;                 // d m / d (range, bearing)
};

// The inverse measurement: where a landmark seen at range z(0), bearing z(1) from robot state x lies (table 10.1,
// lines 9-10), with the Jacobians that give its covariance G_robot P_rr G_robot^T + G_z Q G_z^T and its correlation
// G_robot P_r* with the rest of the state.
template <int D>
LandmarkFromRangeBearing<D> landmark_from_range_bearing(const Eigen::Matrix<float, D, 1>& x, const Eigen::Vector2f& z) {
  static_assert(D == 2 || D == 3, "robot state is (x, y) or (x, y, theta)");
  LandmarkFromRangeBearing<D> out;
  float a = z(1);
  if constexpr (D == 3) a += x(2);
  float s = 0.0f, c = 0.0f;
  fmath::sincos(a, s, c);
  const float r = z(0);
  out.m << x(0) + r * c, x(1) + r * s;
  out.G_robot.setZero();
  out.G_robot(0, 0) = 1.0f;
  out.G_robot(1, 1) = 1.0f;
  if constexpr (D == 3) {
    out.G_robot(0, 2) = -r * s;
    out.G_robot(1, 2) = r * c;
  }
  out.G_z << c, -r * s, s, r * c;
  return out;
}

}  // namespace est
