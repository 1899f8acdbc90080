#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "est/motion/omni_model.hpp"
#include "pose_density_check.hpp"
#include "statistics.hpp"

namespace {

using est::MotionStatus;
using est::OmniControl;
using est::OmniMotionModel;
using est::OmniParams;
using est::Pose2;

std::array<double, 3> dv(const Pose2& x) { return {x.x, x.y, x.theta}; }
double wrap(double a) { return std::remainder(a, 2.0 * 3.14159265358979323846); }

// Thrun eq. 5.9 extended by the sideways speed, integrated by hand: the ICR sits at (-v2, v1) / w in the body frame.
std::array<double, 3> icr_reference(double x, double y, double th, double v1, double v2, double w, double dt) {
  if (w == 0.0)
    return {x + dt * (v1 * std::cos(th) - v2 * std::sin(th)), y + dt * (v1 * std::sin(th) + v2 * std::cos(th)), th};
  const double cx = x + (-v2 * std::cos(th) - v1 * std::sin(th)) / w;
  const double cy = y + (-v2 * std::sin(th) + v1 * std::cos(th)) / w;
  const double turn = w * dt, px = x - cx, py = y - cy;
  return {cx + std::cos(turn) * px - std::sin(turn) * py, cy + std::sin(turn) * px + std::cos(turn) * py, th + turn};
}

OmniParams noisy_params() {
  OmniParams p;
  const float a[9] = {0.1f, 0.02f, 0.02f, 0.02f, 0.15f, 0.02f, 0.02f, 0.02f, 0.15f};
  for (int i = 0; i < 9; ++i) p.alpha[i] = a[i];
  p.dt = 1.0f;
  return p;
}

std::vector<std::array<double, 3>> draw(const Pose2& x0, const OmniControl& u, const OmniParams& p, int n,
                                        std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(dv(OmniMotionModel::sample(x0, u, p, rng)));
  return out;
}


}  // namespace

TEST_CASE("omni without noise: forward, sideways and turning about the ICR (hand-computed pose)", "[omni]") {
  OmniParams p;
  p.dt = 1.0f;
  // v1 = 1, v2 = 0.5 m/s, w = 1 rad/s for 1 s. By hand: x' = (v1 sin 1 - v2 (1 - cos 1)), y' = (v1 (1 - cos 1) +
  // v2 sin 1) = (0.6116221, 0.8804332), theta' = 1.
  const Pose2 x = OmniMotionModel::predict({0.0f, 0.0f, 0.0f}, {1.0f, 0.5f, 1.0f}, p);
  CHECK(x.x == Approx(0.6116221).margin(2e-6));
  CHECK(x.y == Approx(0.8804332).margin(2e-6));
  CHECK(x.theta == Approx(1.0).margin(1e-6));
  // Pure crab to the left at heading pi/2: moves along -x.
  p.dt = 0.5f;
  const Pose2 c = OmniMotionModel::predict({1.0f, 1.0f, static_cast<float>(3.14159265358979323846 / 2)},
                                           {0.0f, 2.0f, 0.0f}, p);
  CHECK(c.x == Approx(0.0).margin(1e-6));
  CHECK(c.y == Approx(1.0).margin(1e-6));
  // Spin in place.
  const Pose2 s = OmniMotionModel::predict({1.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 2.0f}, p);
  CHECK(s.x == 1.0f);
  CHECK(s.y == 1.0f);
  CHECK(s.theta == Approx(1.0).margin(1e-6));
}

TEST_CASE("omni without noise matches the ICR construction over a grid", "[omni]") {
  OmniParams p;
  double worst = 0.0;
  for (double v1 : {-1.0, 0.0, 0.7})
    for (double v2 : {-0.4, 0.0, 0.9})
      for (double w : {-2.0, -0.3, 0.0, 0.5, 3.0})
        for (double th : {-2.5, 1.0})
          for (double dt : {0.05, 1.0}) {
            p.dt = static_cast<float>(dt);
            const OmniControl u{static_cast<float>(v1), static_cast<float>(v2), static_cast<float>(w)};
            const Pose2 x0{0.3f, -0.2f, static_cast<float>(th)};
            const auto q = dv(OmniMotionModel::predict(x0, u, p));
            const auto r = icr_reference(x0.x, x0.y, x0.theta, u.v1, u.v2, u.w, p.dt);
            worst = std::max({worst, std::fabs(q[0] - r[0]), std::fabs(q[1] - r[1]), std::fabs(wrap(q[2] - r[2]))});
          }
  INFO("worst deviation " << worst);
  CHECK(worst < 1e-5);
}

TEST_CASE("omni tiny yaw rate is continuous with the straight line", "[omni]") {
  OmniParams p;
  p.dt = 1.0f;
  const Pose2 x0{0.0f, 0.0f, 0.2f};
  const auto arc_reference = [](double th, double v1, double v2, double w, double dt) {
    const double h = 0.5 * w * dt, k = h == 0.0 ? dt : dt * std::sin(h) / h;
    const double c = std::cos(th + h), s = std::sin(th + h);
    return std::array<double, 3>{k * (c * v1 - s * v2), k * (s * v1 + c * v2), th + 2.0 * h};
  };
  for (double w : {0.0, 1e-30, 1e-7, 1e-4, 0.1999999, 0.2000001, 0.7}) {
    for (double sign : {-1.0, 1.0}) {
      const OmniControl u{1.0f, -0.5f, static_cast<float>(sign * w)};
      const auto q = dv(OmniMotionModel::predict(x0, u, p));
      const auto r = arc_reference(x0.theta, u.v1, u.v2, u.w, p.dt);
      INFO("w = " << sign * w);
      CHECK(std::fabs(q[0] - r[0]) < 2e-6);
      CHECK(std::fabs(q[1] - r[1]) < 2e-6);
      CHECK(std::fabs(q[2] - r[2]) < 2e-6);
    }
  }
}

TEST_CASE("omni sample without noise equals predict, bit for bit", "[omni]") {
  OmniParams p;
  est::Rng rng(5u);
  for (OmniControl u : {OmniControl{1.0f, 0.2f, 0.3f}, OmniControl{0.0f, -1.0f, 0.0f}}) {
    const Pose2 s = OmniMotionModel::sample({1.0f, 1.0f, 1.0f}, u, p, rng);
    const Pose2 e = OmniMotionModel::predict({1.0f, 1.0f, 1.0f}, u, p);
    CHECK(std::memcmp(&s, &e, sizeof s) == 0);
  }
}

TEST_CASE("omni check rejects bad input", "[omni]") {
  const OmniParams p = noisy_params();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 0.2f}, p) == MotionStatus::ok);
  CHECK(OmniMotionModel::check({nan, 0.1f, 0.2f}, p) == MotionStatus::rejected_nonfinite);
  CHECK(OmniMotionModel::check({1.0f, inf, 0.2f}, p) == MotionStatus::rejected_nonfinite);
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 1e3f}, p) == MotionStatus::rejected_range);
  OmniParams bad = p;
  bad.dt = 0.0f;
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 0.2f}, bad) == MotionStatus::rejected_range);
  bad.dt = -1.0f;
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 0.2f}, bad) == MotionStatus::rejected_range);
  bad.dt = nan;
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 0.2f}, bad) == MotionStatus::rejected_nonfinite);
  bad = p;
  bad.alpha[4] = -0.1f;
  CHECK(OmniMotionModel::check({1.0f, 0.1f, 0.2f}, bad) == MotionStatus::rejected_range);

  est::Rng r(9u);
  const est::Rng before = r;
  const Pose2 kept = OmniMotionModel::sample({1.0f, 2.0f, 3.0f}, {nan, 0.0f, 0.0f}, p, r);
  CHECK(kept.x == 1.0f);
  CHECK(kept.theta == 3.0f);
  CHECK(r == before);
  CHECK(OmniMotionModel::likelihood({1.0f, 2.0f, 3.0f}, {nan, 0.0f, 0.0f}, {1.0f, 2.0f, 3.0f}, p) == 0.0f);
  CHECK(OmniMotionModel::log_likelihood({nan, 2.0f, 3.0f}, {1.0f, 0.0f, 0.0f}, {1.0f, 2.0f, 3.0f}, p) ==
        est::motion_density::kLogZero);
  // Zero noise: a point mass; the density stays finite (floored sigma, clamped log), never NaN or inf.
  const OmniParams exact{};
  const float at = OmniMotionModel::likelihood(OmniMotionModel::predict({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.5f}, exact),
                                               {1.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.0f}, exact);
  CHECK(std::isfinite(at));
  CHECK(at > 0.0f);
}

TEST_CASE("omni likelihood agrees with the sample histogram (chi-square, alpha = 0.001)", "[omni][density]") {
  struct Case {
    const char* name;
    OmniControl u;
    Pose2 x0;
  };
  const Case cases[] = {
      {"forward, sideways and turning", {1.0f, 0.5f, 0.8f}, {0.5f, -0.3f, 0.4f}},
      {"pure crab right", {0.0f, -0.8f, 0.0f}, {0.0f, 0.0f, -1.0f}},
      {"fast spin with drift", {0.3f, 0.0f, 2.5f}, {0.0f, 0.0f, -1.5f}},
  };
  for (const Case& c : cases) {
    const OmniParams p = noisy_params();
    const auto samples = draw(c.x0, c.u, p, 100000, 77u);
    const auto box = est::test::box_around(samples, {8, 8, 6});
    const auto f = [&](double x, double y, double t) {
      return static_cast<double>(OmniMotionModel::likelihood(
          {static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, c.u, c.x0, p));
    };
    const auto r = est::test::compare_pose_density(samples, f, box, 0.001);
    INFO(c.name << ": chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV "
                << r.total_variation << " mass in box " << r.mass_in_box);
    CHECK(r.chi2 < r.critical);
    CHECK(r.total_variation < 0.02);  // sampling noise alone gives about 0.009 here
  }
}

TEST_CASE("omni likelihood integrates to one", "[omni][density]") {
  const OmniParams p = noisy_params();
  const OmniControl u{0.8f, -0.3f, 1.2f};
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const auto samples = draw(x0, u, p, 20000, 5u);
  auto box = est::test::box_around(samples, {1, 1, 1});
  const auto f = [&](double x, double y, double t) {
    return static_cast<double>(
        OmniMotionModel::likelihood({static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, u, x0, p));
  };
  std::array<double, 3> lo{}, hi{};
  for (std::size_t e = 0; e < 3; ++e) {  // the +-4 std box widened 1.75 times to +-7 std: the mass outside is < 1e-6
    const double mid = 0.5 * (box.lo[e] + box.hi[e]), half = 0.875 * (box.hi[e] - box.lo[e]);
    lo[e] = mid - half;
    hi[e] = mid + half;
  }
  const double mass = est::test::integrate_grid(f, lo, hi, 6, 1e-6, 3);
  INFO("integral - 1 = " << mass - 1.0);
  // 216 cells refined to 1e-6 each bound the quadrature error by 2.2e-4; measured |1 - integral| < 2e-7.
  CHECK(mass == Approx(1.0).margin(5e-4));
}

TEST_CASE("omni Jacobians match central differences", "[omni][jacobian]") {
  OmniParams p = noisy_params();
  p.dt = 0.5f;
  for (OmniControl u : {OmniControl{1.0f, 0.5f, 0.8f}, OmniControl{-0.5f, 0.2f, 0.0f}, OmniControl{0.0f, 1.0f, 1e-6f},
                        OmniControl{0.3f, -0.7f, -3.0f}}) {
    const Pose2 x0{0.2f, -0.4f, 0.7f};
    const auto j = OmniMotionModel::jacobians(x0, u, p);
    const float e = 1e-3f;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3f dp = Eigen::Vector3f::Zero();
      dp(k) = e;
      const Eigen::Vector3f fd = (OmniMotionModel::predict(Pose2::from_vector(x0.vector() + dp), u, p).vector() -
                                  OmniMotionModel::predict(Pose2::from_vector(x0.vector() - dp), u, p).vector()) /
                                 (2.0f * e);
      for (int r = 0; r < 3; ++r) CHECK(j.G(r, k) == Approx(fd(r)).margin(5e-4));
    }
    for (int k = 0; k < 3; ++k) {
      OmniControl up = u, um = u;
      (k == 0 ? up.v1 : k == 1 ? up.v2 : up.w) += e;
      (k == 0 ? um.v1 : k == 1 ? um.v2 : um.w) -= e;
      const Eigen::Vector3f fd =
          (OmniMotionModel::predict(x0, up, p).vector() - OmniMotionModel::predict(x0, um, p).vector()) / (2.0f * e);
      for (int r = 0; r < 3; ++r) {
        INFO("u = (" << u.v1 << ", " << u.v2 << ", " << u.w << ") column " << k << " row " << r);
        CHECK(j.V(r, k) == Approx(fd(r)).margin(5e-4));
      }
    }
    const float s1 = p.alpha[0] * std::fabs(u.v1) + p.alpha[1] * std::fabs(u.v2) + p.alpha[2] * std::fabs(u.w);
    CHECK(j.M(0, 0) == Approx(s1 * s1));
    CHECK(j.M(0, 2) == 0.0f);
  }
}

TEST_CASE("omni sampling with the same seed gives the same bits", "[omni]") {
  const OmniParams p = noisy_params();
  const OmniControl u{0.7f, 0.3f, 0.2f};
  const auto a = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 42u);
  const auto b = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 42u);
  const auto c = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 43u);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof a[0]) != 0);
}
