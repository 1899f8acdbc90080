#include "est/filter/ekf_localization.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/holonomic_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "est/util/trace.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// The team exercise: 2 point robots, 1 landmark, range-only, 200 steps of shared u and z (sum-of-12 noise, so the
// workload itself needs no transcendental), plus a range-only landmark initialized from the robots' ranges.
void ekf_slam_run(Trace& d) {
  d.scope("coop_ekf_slam");
  using Slam = CooperativeEkfSlam<HolonomicMotionModel, 2, 2>;
  static Slam f;  // 2 KB of state: kept off the stack on the boards
  HolonomicParams mp;
  mp.Q = Eigen::Matrix2f::Identity() * 4.0e-4f;
  const Eigen::Vector2f x0[2] = {Eigen::Vector2f(0.0f, 0.0f), Eigen::Vector2f(4.0f, 0.0f)};
  const Slam::RobotCovariance P0[2] = {Slam::RobotCovariance::Identity() * 0.04f,
                                       Slam::RobotCovariance::Identity() * 0.04f};
  f.init(2, x0, P0);
  f.add_landmark(1, Eigen::Vector2f(2.0f, 3.0f), Eigen::Matrix2f::Identity() * 0.09f);
  Rng rng(5150u);
  Eigen::Vector2f x[2] = {Eigen::Vector2f(0.1f, -0.2f), Eigen::Vector2f(4.2f, 0.1f)};
  const Eigen::Vector2f m(2.2f, 2.9f), m2(-1.0f, 2.0f);
  Eigen::Vector2f u[2];
  for (int k = 0; k < 200; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const float t = 0.05f * static_cast<float>(k);
    u[0] = Eigen::Vector2f(0.09f * (1.0f - t * t / 2.0f + t * t * t * t / 24.0f), 0.03f);
    u[1] = Eigen::Vector2f(-0.04f, 0.08f - 0.0008f * static_cast<float>(k));
    for (int a = 0; a < 2; ++a) {
      // Two statements: the order of evaluation of a call's arguments is unspecified and differs between targets.
      const float wx = sample_normal_sum12(rng, 0.02f);
      const float wy = sample_normal_sum12(rng, 0.02f);
      x[a] += u[a] + Eigen::Vector2f(wx, wy);
    }
    f.predict(u, mp);
    f.correct_robot_range(0, 1, (x[1] - x[0]).norm() + sample_normal_sum12(rng, 0.05f), 0.05f);
    for (int a = 0; a < 2; ++a) {
      f.correct_landmark_range(a, 1, (m - x[a]).norm() + sample_normal_sum12(rng, 0.05f), 0.05f);
      f.correct_landmark_range(a, 2, (m2 - x[a]).norm() + sample_normal_sum12(rng, 0.05f), 0.05f);
    }
    d.add_matrix("mean", f.mean());  // every step's estimate
    d.add_matrix("P", f.covariance());
  }
  const CorrectionCounters& c = f.counters();
  d.step(200);
  d.add_u32("accepted", c.accepted);
  d.add_u32("gated_out", c.gated_out);
  d.add_u32("pending", c.pending);
  d.add_u32("landmarks", static_cast<std::uint32_t>(f.landmarks()));
}

// EKF localization with known correspondences (Thrun table 7.2) through the velocity model, 200 steps, every
// step's estimate traced.
void ekf_localization_run(Trace& d) {
  d.scope("ekf_localization");
  static const Landmark lm[4] = {{0.0f, 0.0f, 1.0f}, {6.0f, 0.0f, 2.0f}, {6.0f, 6.0f, 3.0f}, {0.0f, 6.0f, 4.0f}};
  const LandmarkMap map(lm, 4);
  VelocityParams mp;
  mp.a1 = 0.02f;
  mp.a4 = 0.02f;
  mp.dt = 0.1f;
  EkfLocalization<VelocityMotionModel> f;
  Eigen::Matrix3f P0 = Eigen::Matrix3f::Zero();
  P0.diagonal() << 0.09f, 0.09f, 0.01f;
  f.init(Pose2{3.0f, 1.0f, 0.0f}, P0);
  Rng rng(6160u);
  Pose2 x{3.1f, 0.9f, 0.05f};
  const LandmarkNoise noise{0.1f, 0.03f, 0.0f};
  for (int k = 0; k < 200; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const VelocityControl u{0.6f, 0.3f};
    x = VelocityMotionModel::sample(x, u, mp, rng);
    f.predict(u, mp);
    for (int j = 0; j < 4; ++j) {
      const float dx = lm[j].x - x.x, dy = lm[j].y - x.y;
      const LandmarkMeasurement z{fmath::sqrt(dx * dx + dy * dy) + sample_normal(rng, noise.sigma_range),
                                  fmath::normalize_angle(fmath::atan2(dy, dx) - x.theta +
                                                         sample_normal(rng, noise.sigma_bearing)),
                                  lm[j].signature};
      f.correct_range_bearing(z, map, j, noise);
    }
    d.add_matrix("mean", f.mean_vector());
    d.add_matrix("P", f.covariance());
  }
  d.step(200);
  d.add_u32("accepted", f.counters().accepted);
  d.add_u32("gated_out", f.counters().gated_out);
}

}  // namespace

void section_ekf(Trace& d) {
  ekf_slam_run(d);
  ekf_localization_run(d);
}

}  // namespace est::selftest
