#pragma once
// Holonomic robot (est/motion/holonomic_pose_model.hpp): the twist's (v1, v2) are (u_x, u_y), velocities in the
// robot's frame, so B = dt I; the displacement noise grows with time, Q = dt * noise_per_s (a random walk), and the
// heading drift with its square root.
#include "est/eigen.hpp"
#include "est/loop/control_assembler.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/holonomic_pose_model.hpp"

namespace est::loop {

template <>
struct ControlAssembler<HolonomicPoseMotionModel> {
  struct Config {
    Eigen::Matrix2f noise_per_s = Eigen::Matrix2f::Zero();  // m^2/s
    float heading_sigma_per_sqrt_s = 0.0f;                   // rad/sqrt(s)
  };
  static InputKinds inputs(const Config&) { return InputKind::twist; }
  static ControlStatus make(const MotionInput& m, const Config& c, HolonomicPoseParams& p, Eigen::Vector2f& u) {
    if (!m.twist_known || (m.twist.v1_mps == 0.0f && m.twist.v2_mps == 0.0f)) return ControlStatus::still;
    if (!(m.dt_s > 0.0f)) return ControlStatus::rejected;
    p.point.B = Eigen::Matrix2f::Identity() * m.dt_s;
    p.point.Q = c.noise_per_s * m.dt_s;
    p.heading_sigma = c.heading_sigma_per_sqrt_s * fmath::sqrt(m.dt_s);
    u = {m.twist.v1_mps, m.twist.v2_mps};
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
