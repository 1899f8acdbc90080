#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "est/motion/diff_drive_model.hpp"
#include "pose_density_check.hpp"
#include "statistics.hpp"

namespace {

using est::DiffDriveControl;
using est::DiffDriveMotionModel;
using est::DiffDriveParams;
using est::MotionStatus;
using est::Pose2;
using est::WheelTravel;

constexpr double kPi = 3.14159265358979323846;

std::array<double, 3> dv(const Pose2& x) { return {x.x, x.y, x.theta}; }
double wrap(double a) { return std::remainder(a, 2.0 * kPi); }

// Rotation about the ICR on the axle line, radius R = b/2 (d_r + d_l)/(d_r - d_l), in double.
std::array<double, 3> icr_reference(double x, double y, double th, double dl, double dr, double b) {
  if (dl == dr) return {x + dl * std::cos(th), y + dl * std::sin(th), th};
  const double turn = (dr - dl) / b;
  const double r = 0.5 * b * (dr + dl) / (dr - dl);
  const double cx = x - r * std::sin(th), cy = y + r * std::cos(th);
  const double px = x - cx, py = y - cy;
  return {cx + std::cos(turn) * px - std::sin(turn) * py, cy + std::sin(turn) * px + std::cos(turn) * py, th + turn};
}

DiffDriveParams noisy_params() {
  DiffDriveParams p;
  p.wheel_radius = 0.05f;
  p.track_width = 0.5f;
  p.ticks_per_rev = 1024u;
  p.travel_sigma_per_m = 0.05f;
  p.travel_sigma_floor = 0.01f;
  p.final_rot_sigma = 0.05f;
  return p;
}

std::vector<std::array<double, 3>> draw(const Pose2& x0, const WheelTravel& d, const DiffDriveParams& p, int n,
                                        std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(dv(est::sample_motion_model_diff_drive(d, x0, p, rng)));
  return out;
}


}  // namespace

TEST_CASE("diff drive without noise: ticks to an arc about the ICR (hand-computed pose)", "[diff_drive]") {
  DiffDriveParams p;
  p.wheel_radius = 0.05f;
  p.track_width = 0.5f;
  p.ticks_per_rev = 1000u;
  // 2866 and 3501 ticks of a 5 cm wheel at 1000 ticks/rev: d_l = 0.900380 m, d_r = 1.099872 m. By hand (double):
  // s = 1.000126 m, turn = 0.398982 rad, R = 2.506693 m: (R sin turn, R (1 - cos turn), turn).
  const Pose2 x = DiffDriveMotionModel::predict({0.0f, 0.0f, 0.0f}, {2866, 3501}, p);
  const WheelTravel d = est::wheel_travel_from_ticks({2866, 3501}, p);
  const auto r = icr_reference(0.0, 0.0, 0.0, d.left, d.right, 0.5);
  CHECK(x.x == Approx(r[0]).margin(2e-6));
  CHECK(x.y == Approx(r[1]).margin(2e-6));
  CHECK(x.theta == Approx(r[2]).margin(2e-6));
  CHECK(x.x == Approx(0.9738019).margin(2e-6));
  CHECK(x.y == Approx(0.1968836).margin(2e-6));
  CHECK(x.theta == Approx(0.3989823).margin(2e-6));
  // Equal ticks: straight along the heading. Opposite ticks: a spin in place.
  const Pose2 s = DiffDriveMotionModel::predict({1.0f, 2.0f, 0.5f}, {1000, 1000}, p);
  CHECK(s.x == Approx(1.0 + 2.0 * kPi * 0.05 * std::cos(0.5)).margin(1e-6));
  CHECK(s.y == Approx(2.0 + 2.0 * kPi * 0.05 * std::sin(0.5)).margin(1e-6));
  CHECK(s.theta == 0.5f);
  const Pose2 spin = DiffDriveMotionModel::predict({1.0f, 2.0f, 0.5f}, {-500, 500}, p);
  CHECK(spin.x == 1.0f);
  CHECK(spin.y == 2.0f);
  CHECK(spin.theta == Approx(0.5 + 2.0 * kPi * 0.05 / 0.5).margin(1e-6));
  // Wheel speeds: 20 rad/s on a 5 cm wheel for 0.5 s is 0.5 m.
  const WheelTravel w = est::wheel_travel_from_speeds(20.0f, 20.0f, 0.5f, p);
  CHECK(w.left == Approx(0.5f));
}

TEST_CASE("diff drive without noise matches the ICR construction over a grid", "[diff_drive]") {
  DiffDriveParams p;
  p.track_width = 0.4f;
  double worst = 0.0;
  for (double dl : {-1.0, -0.1, 0.0, 0.3, 1.2})
    for (double dr : {-1.1, -0.1, 0.05, 0.31, 1.2})
      for (double th : {-2.5, 0.0, 1.0}) {
        if (dl == dr) continue;
        const WheelTravel d{static_cast<float>(dl), static_cast<float>(dr)};
        const Pose2 x0{0.3f, -0.2f, static_cast<float>(th)};
        const auto q = dv(est::predict_motion_diff_drive(x0, d, p));
        const auto r = icr_reference(x0.x, x0.y, x0.theta, d.left, d.right, p.track_width);
        worst = std::max({worst, std::fabs(q[0] - r[0]), std::fabs(q[1] - r[1]), std::fabs(wrap(q[2] - r[2]))});
      }
  INFO("worst deviation " << worst);
  CHECK(worst < 1e-5);
}

TEST_CASE("diff drive nearly straight is continuous with the straight line", "[diff_drive]") {
  DiffDriveParams p;
  p.track_width = 0.5f;
  const Pose2 x0{0.0f, 0.0f, 0.2f};
  const auto arc_reference = [](double th, double dl, double dr, double b) {
    const double s = 0.5 * (dl + dr), h = 0.5 * (dr - dl) / b;
    const double chord = h == 0.0 ? s : s * std::sin(h) / h;
    return std::array<double, 3>{chord * std::cos(th + h), chord * std::sin(th + h), th + 2.0 * h};
  };
  // Differences from 1e-7 m up to across the series switch (h = 0.1 at d_r - d_l = 0.1 m).
  for (double e : {0.0, 1e-7, 1e-5, 1e-3, 0.0999999, 0.1000001, 0.3}) {
    for (double sign : {-1.0, 1.0}) {
      const WheelTravel d{static_cast<float>(1.0 - sign * e / 2), static_cast<float>(1.0 + sign * e / 2)};
      const auto q = dv(est::predict_motion_diff_drive(x0, d, p));
      const auto r = arc_reference(x0.theta, d.left, d.right, p.track_width);
      INFO("d_r - d_l = " << sign * e);
      CHECK(std::fabs(q[0] - r[0]) < 2e-6);
      CHECK(std::fabs(q[1] - r[1]) < 2e-6);
      CHECK(std::fabs(q[2] - r[2]) < 2e-6);
    }
  }
}

TEST_CASE("diff drive sample without noise equals predict, bit for bit", "[diff_drive]") {
  DiffDriveParams p;
  est::Rng rng(5u);
  for (DiffDriveControl u : {DiffDriveControl{100, 300}, DiffDriveControl{-50, -50}, DiffDriveControl{0, 0}}) {
    const Pose2 s = DiffDriveMotionModel::sample({1.0f, 1.0f, 1.0f}, u, p, rng);
    const Pose2 e = DiffDriveMotionModel::predict({1.0f, 1.0f, 1.0f}, u, p);
    CHECK(std::memcmp(&s, &e, sizeof s) == 0);
  }
}

TEST_CASE("diff drive check rejects bad input", "[diff_drive]") {
  const DiffDriveParams p = noisy_params();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(DiffDriveMotionModel::check({10, 20}, p) == MotionStatus::ok);
  CHECK(DiffDriveMotionModel::check({DiffDriveControl::kMaxTicks + 1, 0}, p) == MotionStatus::rejected_range);
  CHECK(DiffDriveMotionModel::check({0, -DiffDriveControl::kMaxTicks - 1}, p) == MotionStatus::rejected_range);
  CHECK(est::check_motion_diff_drive(WheelTravel{nan, 0.0f}, p) == MotionStatus::rejected_nonfinite);
  CHECK(est::check_motion_diff_drive(WheelTravel{0.0f, 2e4f}, p) == MotionStatus::rejected_range);
  DiffDriveParams bad = p;
  bad.ticks_per_rev = 0u;
  CHECK(DiffDriveMotionModel::check({10, 20}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.track_width = 0.0f;
  CHECK(DiffDriveMotionModel::check({10, 20}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.wheel_radius = -0.05f;
  CHECK(DiffDriveMotionModel::check({10, 20}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.travel_sigma_floor = -1e-3f;
  CHECK(DiffDriveMotionModel::check({10, 20}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.final_rot_sigma = nan;
  CHECK(DiffDriveMotionModel::check({10, 20}, bad) == MotionStatus::rejected_nonfinite);

  // Rejected: the pose is left as it was, nothing is drawn, the likelihood is zero, the Jacobians neutral.
  est::Rng r(9u);
  const est::Rng before = r;
  bad = p;
  bad.ticks_per_rev = 0u;
  const Pose2 kept = DiffDriveMotionModel::sample({1.0f, 2.0f, 3.0f}, {10, 20}, bad, r);
  CHECK(kept.x == 1.0f);
  CHECK(kept.theta == 3.0f);
  CHECK(r == before);
  CHECK(DiffDriveMotionModel::likelihood({1.0f, 2.0f, 3.0f}, {10, 20}, {1.0f, 2.0f, 3.0f}, bad) == 0.0f);
  const auto j = DiffDriveMotionModel::jacobians({0.0f, 0.0f, 0.0f}, {10, 20}, bad);
  CHECK(j.G.isIdentity());
  CHECK(j.V.isZero());
  // A NaN pose has density 0, never NaN.
  CHECK(DiffDriveMotionModel::likelihood({nan, 0.0f, 0.0f}, {10, 20}, {0.0f, 0.0f, 0.0f}, p) == 0.0f);
}

TEST_CASE("diff drive likelihood agrees with the sample histogram (chi-square, alpha = 0.001)",
          "[diff_drive][density]") {
  struct Case {
    const char* name;
    WheelTravel d;
    Pose2 x0;
  };
  const Case cases[] = {
      {"curve left, d = (0.9, 1.1) m", {0.9f, 1.1f}, {0.5f, -0.3f, 0.4f}},
      {"straight back, d = (-0.5, -0.5) m", {-0.5f, -0.5f}, {0.0f, 0.0f, -1.0f}},
      {"tight right turn, d = (0.6, 0.1) m", {0.6f, 0.1f}, {0.0f, 0.0f, 0.0f}},
  };
  for (const Case& c : cases) {
    const DiffDriveParams p = noisy_params();
    const auto samples = draw(c.x0, c.d, p, 100000, 77u);
    const auto box = est::test::box_around(samples, {8, 8, 6});
    const auto f = [&](double x, double y, double t) {
      return static_cast<double>(est::motion_model_diff_drive(
          {static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, c.d, c.x0, p));
    };
    const auto r = est::test::compare_pose_density(samples, f, box, 0.001);
    INFO(c.name << ": chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV "
                << r.total_variation << " mass in box " << r.mass_in_box);
    CHECK(r.chi2 < r.critical);
    CHECK(r.total_variation < 0.02);  // sampling noise alone gives about 0.009 here
  }
}

TEST_CASE("diff drive likelihood integrates to one", "[diff_drive][density]") {
  const DiffDriveParams p = noisy_params();
  const WheelTravel d{0.7f, 1.0f};
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const auto samples = draw(x0, d, p, 20000, 5u);
  auto box = est::test::box_around(samples, {1, 1, 1});
  const auto f = [&](double x, double y, double t) {
    return static_cast<double>(
        est::motion_model_diff_drive({static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, d, x0, p));
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

TEST_CASE("diff drive Jacobians match central differences", "[diff_drive][jacobian]") {
  const DiffDriveParams p = noisy_params();
  for (DiffDriveControl u : {DiffDriveControl{3000, 3500}, DiffDriveControl{-2000, 1000}, DiffDriveControl{700, 700},
                             DiffDriveControl{-1500, -1501}}) {
    const Pose2 x0{0.2f, -0.4f, 0.7f};
    const auto j = DiffDriveMotionModel::jacobians(x0, u, p);
    const float e = 1e-3f;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3f dp = Eigen::Vector3f::Zero();
      dp(k) = e;
      const Eigen::Vector3f fd = (DiffDriveMotionModel::predict(Pose2::from_vector(x0.vector() + dp), u, p).vector() -
                                  DiffDriveMotionModel::predict(Pose2::from_vector(x0.vector() - dp), u, p).vector()) /
                                 (2.0f * e);
      for (int r = 0; r < 3; ++r) CHECK(j.G(r, k) == Approx(fd(r)).margin(5e-4));
    }
    // Per tick: difference over +-8 ticks (the map is smooth in the travel; ticks are only its unit).
    const WheelTravel d = est::wheel_travel_from_ticks(u, p);
    const float m = est::diff_drive_m_per_tick(p) * 8.0f;
    const auto g = [&](float l, float r) { return est::predict_motion_diff_drive(x0, {l, r}, p).vector(); };
    const Eigen::Vector3f fl = (g(d.left + m, d.right) - g(d.left - m, d.right)) / 16.0f;
    const Eigen::Vector3f fr = (g(d.left, d.right + m) - g(d.left, d.right - m)) / 16.0f;
    for (int r = 0; r < 3; ++r) {
      INFO("ticks " << u.left_ticks << ", " << u.right_ticks << " row " << r);
      CHECK(j.V(r, 0) == Approx(fl(r)).margin(2e-6));
      CHECK(j.V(r, 1) == Approx(fr(r)).margin(2e-6));
    }
    const float sl = p.travel_sigma_per_m * std::fabs(d.left) + p.travel_sigma_floor;
    const float mpt = est::diff_drive_m_per_tick(p);
    CHECK(j.M(0, 0) == Approx(sl * sl / (mpt * mpt)).epsilon(1e-5));
    CHECK(j.M(0, 1) == 0.0f);
  }
}

TEST_CASE("diff drive sampling with the same seed gives the same bits", "[diff_drive]") {
  const DiffDriveParams p = noisy_params();
  const WheelTravel d{0.3f, 0.5f};
  const auto a = draw({0.0f, 0.0f, 0.0f}, d, p, 1000, 42u);
  const auto b = draw({0.0f, 0.0f, 0.0f}, d, p, 1000, 42u);
  const auto c = draw({0.0f, 0.0f, 0.0f}, d, p, 1000, 43u);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof a[0]) != 0);
}
