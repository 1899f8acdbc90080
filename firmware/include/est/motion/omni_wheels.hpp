#pragma once
// Wheel kinematics of an omnidirectional base, for its encoders: each wheel's travel is linear in the body's
// displacement (dx forward, dy left, dtheta counter-clockwise) over a step, s = J (dx, dy, dtheta)^T with one row per
// wheel; the displacement from N >= 3 measured travels is the least-squares inverse (J^T J)^-1 J^T s (exact for
// three wheels, and for four when their travels agree). Rows for the two common bases are given: three or four omni
// wheels on a circle (kiwi), and four mecanum wheels in the X arrangement.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/math/fmath.hpp"

namespace est {

inline constexpr std::int32_t kMaxOmniWheels = 4;

struct OmniWheels {
  std::uint8_t count = 0;                       // 3 or 4; 0: not configured
  float metres_per_tick = 0.0f;                 // wheel travel per encoder tick
  float rows[kMaxOmniWheels][3] = {};           // J: travel per unit (dx, dy, dtheta) in m, m, m/rad
  Eigen::Matrix<float, 3, kMaxOmniWheels> body_from_travel = Eigen::Matrix<float, 3, kMaxOmniWheels>::Zero();
};

// Configures `w` from J's rows; false (and count 0) unless 3 <= count <= 4, metres_per_tick > 0 and J has rank 3.
inline bool configure_omni_wheels(OmniWheels& w, const float (*rows)[3], std::int32_t count, float metres_per_tick) {
  w = OmniWheels{};
  if (count < 3 || count > kMaxOmniWheels || !(metres_per_tick > 0.0f) || !fmath::isfinite(metres_per_tick))
    return false;
  Eigen::Matrix<float, kMaxOmniWheels, 3> J = Eigen::Matrix<float, kMaxOmniWheels, 3>::Zero();
  for (std::int32_t i = 0; i < count; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!fmath::isfinite(rows[i][j])) return false;
      J(i, j) = rows[i][j];
      w.rows[i][j] = rows[i][j];
    }
  const Eigen::Matrix3f A = J.transpose() * J;
  // (J^T J)^-1 by cofactors (symmetric 3 x 3).
  Eigen::Matrix3f C;
  C(0, 0) = A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1);
  C(0, 1) = A(0, 2) * A(2, 1) - A(0, 1) * A(2, 2);
  C(0, 2) = A(0, 1) * A(1, 2) - A(0, 2) * A(1, 1);
  C(1, 0) = A(1, 2) * A(2, 0) - A(1, 0) * A(2, 2);
  C(1, 1) = A(0, 0) * A(2, 2) - A(0, 2) * A(2, 0);
  C(1, 2) = A(0, 2) * A(1, 0) - A(0, 0) * A(1, 2);
  C(2, 0) = A(1, 0) * A(2, 1) - A(1, 1) * A(2, 0);
  C(2, 1) = A(0, 1) * A(2, 0) - A(0, 0) * A(2, 1);
  C(2, 2) = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  const float det = A(0, 0) * C(0, 0) + A(0, 1) * C(1, 0) + A(0, 2) * C(2, 0);
  if (!(fmath::abs(det) > 1.0e-9f) || !fmath::isfinite(det)) return false;
  w.body_from_travel = (C / det) * J.transpose();
  w.count = static_cast<std::uint8_t>(count);
  w.metres_per_tick = metres_per_tick;
  return true;
}

// Omni wheels at angles beta_i (rad, counter-clockwise from forward) on a circle of radius `radius` about the body's
// centre, each rolling tangentially (counter-clockwise positive): s_i = -sin(beta_i) dx + cos(beta_i) dy + radius dtheta.
inline void omni_wheel_rows(const float* beta, std::int32_t count, float radius, float (*rows)[3]) {
  for (std::int32_t i = 0; i < count; ++i) {
    float s = 0.0f, c = 0.0f;
    fmath::sincos(beta[i], s, c);
    rows[i][0] = -s;
    rows[i][1] = c;
    rows[i][2] = radius;
  }
}

// Mecanum wheels, X arrangement, in the order front-left, front-right, rear-left, rear-right; half the wheelbase
// lx and half the track ly (m): s = dx -+ dy -+ (lx + ly) dtheta with the signs of each corner.
inline void mecanum_wheel_rows(float lx, float ly, float (*rows)[3]) {
  const float k = lx + ly;
  const float r[4][3] = {{1.0f, -1.0f, -k}, {1.0f, 1.0f, k}, {1.0f, 1.0f, -k}, {1.0f, -1.0f, k}};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) rows[i][j] = r[i][j];
}

// The body displacement (dx, dy, dtheta) of tick increments.
inline Eigen::Vector3f omni_body_displacement(const OmniWheels& w, const std::int32_t* ticks) {
  Eigen::Matrix<float, kMaxOmniWheels, 1> s = Eigen::Matrix<float, kMaxOmniWheels, 1>::Zero();
  for (std::int32_t i = 0; i < w.count; ++i) s(i) = static_cast<float>(ticks[i]) * w.metres_per_tick;
  return w.body_from_travel * s;
}

}  // namespace est
