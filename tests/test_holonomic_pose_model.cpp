// The holonomic point robot carrying a heading it never steers (est/motion/holonomic_pose_model.hpp): its density
// integrates to one over (x, y, theta) and matches the sampler's histogram, the sampler's moments are the model's,
// the EKF Jacobians match finite differences, and at theta = 0 it is the point robot of est/motion/holonomic_model.hpp.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "est/motion/holonomic_model.hpp"
#include "est/motion/holonomic_pose_model.hpp"
#include "pose_density_check.hpp"
#include "statistics.hpp"

namespace {

using est::HolonomicPoseMotionModel;
using est::HolonomicPoseParams;
using est::Pose2;
using Vec2 = Eigen::Vector2f;

double d(float f) { return static_cast<double>(f); }

// Correlated displacement noise (std 0.05 m and 0.08 m in the robot frame, correlation 0.4), B a velocity over
// dt = 0.5 s, and a heading drift of 0.03 rad per step.
HolonomicPoseParams params() {
  HolonomicPoseParams p;
  p.point.B = Eigen::Matrix2f::Identity() * 0.5f;
  p.point.Q << 0.0025f, 0.0016f, 0.0016f, 0.0064f;
  p.heading_sigma = 0.03f;
  return p;
}

std::vector<std::array<double, 3>> draw(const Pose2& x0, const Vec2& u, const HolonomicPoseParams& p, int n,
                                        std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Pose2 x = HolonomicPoseMotionModel::sample(x0, u, p, rng);
    out.push_back({d(x.x), d(x.y), d(x.theta)});
  }
  return out;
}

}  // namespace

TEST_CASE("holonomic pose: the displacement is B u in the robot's frame and the heading never changes without drift",
          "[holonomic_pose]") {
  HolonomicPoseParams p;
  p.point.B = Eigen::Matrix2f::Identity() * 0.1f;
  const Pose2 x0{1.0f, 2.0f, 0.5f * est::kPi};
  const Pose2 x = HolonomicPoseMotionModel::predict(x0, Vec2(1.0f, 0.5f), p);
  CHECK(d(x.x) == Approx(1.0 - 0.05).margin(1e-6));  // facing +y: the robot's left is world -x
  CHECK(d(x.y) == Approx(2.0 + 0.1).margin(1e-6));
  CHECK(x.theta == x0.theta);
  est::Rng rng(3u);
  const Pose2 s = HolonomicPoseMotionModel::sample(x0, Vec2(1.0f, 0.5f), p, rng);  // Q = 0, no drift: exact
  CHECK(s.x == x.x);
  CHECK(s.y == x.y);
  CHECK(s.theta == x0.theta);
}

TEST_CASE("holonomic pose at theta = 0 is the point robot: the same draws, the same mean, the same density",
          "[holonomic_pose]") {
  HolonomicPoseParams p = params();
  p.heading_sigma = 0.0f;
  const Vec2 u(0.4f, -0.2f);
  est::Rng a(11u), b(11u);
  for (int i = 0; i < 200; ++i) {
    // The same random numbers, the same sample (to the rounding of the additions' order).
    const Pose2 x = HolonomicPoseMotionModel::sample({0.3f, -0.1f, 0.0f}, u, p, a);
    const Vec2 y = est::HolonomicMotionModel::sample(Vec2(0.3f, -0.1f), u, p.point, b);
    REQUIRE(d(x.x) == Approx(d(y(0))).margin(1e-6));
    REQUIRE(d(x.y) == Approx(d(y(1))).margin(1e-6));
    CHECK(x.theta == 0.0f);
  }
  CHECK(a.next() == b.next());  // and no draw more or less
  const Pose2 p0 = HolonomicPoseMotionModel::predict({0.3f, -0.1f, 0.0f}, u, p);
  const Vec2 q0 = est::HolonomicMotionModel::predict(Vec2(0.3f, -0.1f), u, p.point);
  CHECK(p0.x == q0(0));
  CHECK(p0.y == q0(1));
  // With a heading drift the position marginal is still the point robot's: the log density splits into the point
  // robot's plus the heading's normal.
  p.heading_sigma = 0.05f;
  const Pose2 at{0.52f, -0.2f, 0.03f};
  const float pose = HolonomicPoseMotionModel::log_likelihood(at, u, {0.3f, -0.1f, 0.0f}, p);
  const float point = est::HolonomicMotionModel::log_likelihood(Vec2(0.52f, -0.2f), u, Vec2(0.3f, -0.1f), p.point);
  const double heading = -0.5 * std::pow(0.03 / 0.05, 2) - std::log(0.05 * std::sqrt(2.0 * M_PI));
  CHECK(d(pose) == Approx(d(point) + heading).margin(1e-4));
}

TEST_CASE("holonomic pose samples have the model's moments: mean R B u, covariance R Q R^T, heading variance",
          "[holonomic_pose]") {
  const HolonomicPoseParams p = params();
  const Pose2 x0{2.0f, -1.0f, 0.7f};
  const Vec2 u(0.6f, 0.2f);
  const int n = 200000;
  const auto s = draw(x0, u, p, n, 17u);
  const double c = std::cos(0.7), sn = std::sin(0.7);
  const double bx = 0.3, by = 0.1;  // B u
  const double mx = 2.0 + c * bx - sn * by, my = -1.0 + sn * bx + c * by;
  // R Q R^T
  const double q11 = 0.0025, q12 = 0.0016, q22 = 0.0064;
  const double r11 = c * c * q11 - 2 * c * sn * q12 + sn * sn * q22;
  const double r22 = sn * sn * q11 + 2 * c * sn * q12 + c * c * q22;
  const double r12 = c * sn * (q11 - q22) + (c * c - sn * sn) * q12;
  double s0 = 0, s1 = 0, s2 = 0, s00 = 0, s11 = 0, s01 = 0, s22 = 0, s02 = 0;
  for (const auto& x : s) {
    const double a = x[0] - mx, b = x[1] - my, t = x[2] - 0.7;
    s0 += a;
    s1 += b;
    s2 += t;
    s00 += a * a;
    s11 += b * b;
    s01 += a * b;
    s22 += t * t;
    s02 += a * t;
  }
  const double nn = n;
  CHECK(std::fabs(s0 / nn) < 5 * std::sqrt(r11 / nn));
  CHECK(std::fabs(s1 / nn) < 5 * std::sqrt(r22 / nn));
  CHECK(std::fabs(s2 / nn) < 5 * std::sqrt(0.03 * 0.03 / nn));
  CHECK(std::fabs(s00 / nn - r11) < 5 * std::sqrt(2 * r11 * r11 / nn));
  CHECK(std::fabs(s11 / nn - r22) < 5 * std::sqrt(2 * r22 * r22 / nn));
  CHECK(std::fabs(s01 / nn - r12) < 5 * std::sqrt((r12 * r12 + r11 * r22) / nn));
  CHECK(std::fabs(s22 / nn - 0.0009) < 5 * std::sqrt(2 * 0.0009 * 0.0009 / nn));
  CHECK(std::fabs(s02 / nn) < 5 * std::sqrt(r11 * 0.0009 / nn));  // the drift is independent of the displacement
}

TEST_CASE("holonomic pose likelihood integrates to one over (x, y, theta) and matches the sampler's histogram",
          "[holonomic_pose][density]") {
  const HolonomicPoseParams p = params();
  struct Case {
    const char* name;
    Pose2 x0;
    Vec2 u;
  };
  for (const Case& c : {Case{"heading 0.7", {2.0f, -1.0f, 0.7f}, Vec2(0.6f, 0.2f)},
                        Case{"heading near -pi", {0.0f, 0.0f, -3.1f}, Vec2(-0.3f, 0.5f)}}) {
    INFO(c.name);
    const auto samples = draw(c.x0, c.u, p, 100000, 23u);
    const auto f = [&](double x, double y, double t) {
      return static_cast<double>(HolonomicPoseMotionModel::likelihood(
          {static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, c.u, c.x0, p));
    };
    // Mass over +-7 sample standard deviations of each coordinate (the heading box crosses +-pi for the second
    // case: the density is in the wrapped heading difference, so theta beyond pi is the same angle).
    auto box = est::test::box_around(samples, {1, 1, 1});
    std::array<double, 3> lo{}, hi{};
    for (std::size_t e = 0; e < 3; ++e) {
      const double mid = 0.5 * (box.lo[e] + box.hi[e]), half = 0.875 * (box.hi[e] - box.lo[e]);
      lo[e] = mid - half;
      hi[e] = mid + half;
    }
    if (c.x0.theta < -3.0f) {  // samples wrap to +pi: integrate around the unwrapped start heading instead
      lo[2] = d(c.x0.theta) - 7.0 * 0.03;
      hi[2] = d(c.x0.theta) + 7.0 * 0.03;
    }
    const double mass = est::test::integrate_grid(f, lo, hi, 5, 1e-6, 3);
    INFO("integral - 1 = " << mass - 1.0);
    CHECK(mass == Approx(1.0).margin(5e-4));
    if (c.x0.theta > -3.0f) {
      const auto hist_box = est::test::box_around(samples, {8, 8, 6});
      const auto r = est::test::compare_pose_density(samples, f, hist_box, 0.001);
      INFO("chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV " << r.total_variation);
      CHECK(r.chi2 < r.critical);
      CHECK(r.total_variation < 0.02);
    }
  }
}

TEST_CASE("holonomic pose without heading drift is a point mass in heading: finite, and off it nearly zero",
          "[holonomic_pose][density]") {
  HolonomicPoseParams p = params();
  p.heading_sigma = 0.0f;
  const Pose2 x0{0.0f, 0.0f, 0.4f};
  const Vec2 u(0.2f, 0.0f);
  const Pose2 mean = HolonomicPoseMotionModel::predict(x0, u, p);
  const float on = HolonomicPoseMotionModel::log_likelihood(mean, u, x0, p);
  const float off = HolonomicPoseMotionModel::log_likelihood({mean.x, mean.y, 0.45f}, u, x0, p);
  CHECK(std::isfinite(on));
  CHECK(std::isfinite(off));
  CHECK(on > off + 100.0f);
  const float nan = HolonomicPoseMotionModel::log_likelihood({std::nanf(""), 0.0f, 0.4f}, u, x0, p);
  CHECK(nan == est::motion_density::kLogZero);
}

TEST_CASE("holonomic pose Jacobians match central differences; V M V^T is the displacement noise R Q R^T",
          "[holonomic_pose][jacobian]") {
  const HolonomicPoseParams p = params();
  for (const Pose2& x0 : {Pose2{0.2f, -0.4f, 0.7f}, Pose2{1.0f, 2.0f, -2.5f}, Pose2{0.0f, 0.0f, 0.0f}}) {
    const Vec2 u(0.6f, -0.3f);
    const auto j = HolonomicPoseMotionModel::jacobians(x0, u, p);
    const float e = 1e-3f;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3f dp = Eigen::Vector3f::Zero();
      dp(k) = e;
      const Eigen::Vector3f fd =
          (HolonomicPoseMotionModel::predict(Pose2::from_vector(x0.vector() + dp), u, p).vector() -
           HolonomicPoseMotionModel::predict(Pose2::from_vector(x0.vector() - dp), u, p).vector()) /
          (2.0f * e);
      for (int r = 0; r < 3; ++r) CHECK(j.G(r, k) == Approx(fd(r)).margin(5e-4));
    }
    for (int k = 0; k < 2; ++k) {
      Vec2 du = Vec2::Zero();
      du(k) = e;
      const Eigen::Vector3f fd = (HolonomicPoseMotionModel::predict(x0, u + du, p).vector() -
                                  HolonomicPoseMotionModel::predict(x0, u - du, p).vector()) /
                                 (2.0f * e);
      for (int r = 0; r < 3; ++r) CHECK(j.V(r, k) == Approx(fd(r)).margin(5e-4));
    }
    const float c = std::cos(x0.theta), s = std::sin(x0.theta);
    Eigen::Matrix2f R;
    R << c, -s, s, c;
    const Eigen::Matrix3f vmv = j.V * j.M * j.V.transpose();
    const Eigen::Matrix2f want = R * p.point.Q * R.transpose();
    for (int r = 0; r < 2; ++r)
      for (int k = 0; k < 2; ++k) CHECK(vmv(r, k) == Approx(want(r, k)).margin(1e-7));
    CHECK(vmv(2, 2) == 0.0f);  // the drift is the EKF's own process noise, not the control's
  }
}

TEST_CASE("holonomic pose check refuses a bad heading drift and everything the point robot refuses",
          "[holonomic_pose]") {
  using est::MotionStatus;
  HolonomicPoseParams p = params();
  CHECK(HolonomicPoseMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::ok);
  CHECK(HolonomicPoseMotionModel::check(Vec2(std::nanf(""), 2.0f), p) == MotionStatus::rejected_nonfinite);
  p.heading_sigma = -0.1f;
  CHECK(HolonomicPoseMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
  p.heading_sigma = std::nanf("");
  CHECK(HolonomicPoseMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_nonfinite);
  p = params();
  p.point.B.setZero();
  CHECK(HolonomicPoseMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
}

TEST_CASE("holonomic pose sampling with the same seed gives the same bits", "[holonomic_pose]") {
  const HolonomicPoseParams p = params();
  const auto a = draw({0.0f, 0.0f, 1.0f}, Vec2(0.3f, 0.1f), p, 1000, 42u);
  const auto b = draw({0.0f, 0.0f, 1.0f}, Vec2(0.3f, 0.1f), p, 1000, 42u);
  const auto c = draw({0.0f, 0.0f, 1.0f}, Vec2(0.3f, 0.1f), p, 1000, 43u);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof a[0]) != 0);
}
