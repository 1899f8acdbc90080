#include "est/geometry/pose2.hpp"
#include "est/motion/holonomic_model.hpp"
#include "est/motion/odometry_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/util/trace.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

void add_pose(Trace& d, const Pose2& x) {
  d.add("x", x.x);
  d.add("y", x.y);
  d.add("theta", x.theta);
}

}  // namespace

// Velocity (tables 5.1, 5.3, 7.2), odometry (tables 5.5, 5.6) and holonomic models: a sampled trajectory of 256
// steps each (including the straight and turn-in-place cases), the density of every sample, and the Jacobians.
void section_motion_a(Trace& d) {
  Rng rng(5150u);

  VelocityParams vp;
  vp.a1 = 0.01f;
  vp.a2 = 0.002f;
  vp.a3 = 0.004f;
  vp.a4 = 0.004f;
  vp.a5 = 0.001f;
  vp.a6 = 0.001f;
  vp.dt = 0.1f;
  Pose2 x{};
  d.scope("velocity");
  for (int k = 0; k < 256; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const float w = (k % 4 == 0) ? 0.0f : (k % 4 == 1 ? 1e-7f : 0.01f * static_cast<float>(k - 128));
    const VelocityControl u{(k % 8 == 7) ? 0.0f : 1.0f - 0.01f * static_cast<float>(k), w};
    const Pose2 next = VelocityMotionModel::sample(x, u, vp, rng);
    add_pose(d, next);
    d.add("log_p", VelocityMotionModel::log_likelihood(next, u, x, vp));
    d.add("p", VelocityMotionModel::likelihood(next, u, x, vp));
    d.add_matrix("V", VelocityMotionModel::jacobians(x, u, vp).V);
    x = next;
  }

  OdometryParams op;
  op.a1 = 0.02f;
  op.a2 = 0.01f;
  op.a3 = 0.01f;
  op.a4 = 0.005f;
  Pose2 odom{10.0f, -4.0f, 1.0f};
  x = Pose2{};
  d.scope("odometry");
  for (int k = 0; k < 256; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const float step = (k % 5 == 0) ? 0.0f : 0.05f;  // every fifth step a pure rotation
    const Pose2 next_odom{odom.x + step * fmath::cos(odom.theta), odom.y + step * fmath::sin(odom.theta),
                          fmath::normalize_angle(odom.theta + 0.03f * static_cast<float>(k % 7 - 3))};
    const OdometryControl u{odom, next_odom};
    const Pose2 next = OdometryMotionModel::sample(x, u, op, rng);
    add_pose(d, next);
    d.add("log_p", OdometryMotionModel::log_likelihood(next, u, x, op));
    d.add_matrix("V", OdometryMotionModel::jacobians(x, u, op).V);
    d.add_matrix("M", OdometryMotionModel::jacobians(x, u, op).M);
    x = next;
    odom = next_odom;
  }

  HolonomicParams hp;
  hp.B << 0.5f, 0.1f, 0.0f, 0.5f;
  hp.Q << 0.01f, 0.003f, 0.003f, 0.0025f;
  Eigen::Vector2f p = Eigen::Vector2f::Zero();
  d.scope("holonomic");
  for (int k = 0; k < 256; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const Eigen::Vector2f u(0.2f, -0.1f * static_cast<float>(k % 3));
    const Eigen::Vector2f next = HolonomicMotionModel::sample(p, u, hp, rng);
    d.add_matrix("p", next);
    d.add("log_p", HolonomicMotionModel::log_likelihood(next, u, p, hp));
    p = next;
  }
  d.step(256);
  d.add_matrix("M", HolonomicMotionModel::jacobians(p, Eigen::Vector2f::Zero(), hp).M);
}

}  // namespace est::selftest
