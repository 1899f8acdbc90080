#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "est/motion/bicycle_model.hpp"
#include "pose_density_check.hpp"
#include "statistics.hpp"

namespace {

using est::BicycleControl;
using est::BicycleMotionModel;
using est::BicycleParams;
using est::MotionStatus;
using est::Pose2;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The front wheel rotated about the ICR, in double: where the rear axle line meets the front wheel's normal.
std::array<double, 3> icr_reference(double x, double y, double th, double v, double a, double dt, double l) {
  if (a == 0.0) return {x + v * dt * std::cos(th), y + v * dt * std::sin(th), th};
  const double rear_x = x - l * std::cos(th), rear_y = y - l * std::sin(th);
  const double r_rear = l / std::tan(a);
  const double cx = rear_x - r_rear * std::sin(th), cy = rear_y + r_rear * std::cos(th);
  const double turn = v * std::sin(a) / l * dt;
  const double px = x - cx, py = y - cy;
  return {cx + std::cos(turn) * px - std::sin(turn) * py, cy + std::sin(turn) * px + std::cos(turn) * py, th + turn};
}

std::array<double, 3> dv(const Pose2& x) { return {x.x, x.y, x.theta}; }

double wrap(double a) { return std::remainder(a, 2.0 * 3.14159265358979323846); }

BicycleParams noisy_params() {
  BicycleParams p;
  p.frame_length = 1.0f;
  p.steer_max = static_cast<float>(80.0 * kDeg);
  p.steer_sigma = static_cast<float>(5.0 * kDeg);
  p.speed_var_per_speed = 0.01f;  // sigma_v = 0.1 m/s at 1 m/s
  p.final_rot_sigma = 0.08f;
  p.dt = 1.0f;
  return p;
}

std::vector<std::array<double, 3>> draw(const Pose2& x0, const BicycleControl& u, const BicycleParams& p, int n,
                                        std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Pose2 s = BicycleMotionModel::sample(x0, u, p, rng);
    out.push_back({s.x, s.y, s.theta});
  }
  return out;
}

// Box of mean +- 4 std per axis of the samples.

}  // namespace

TEST_CASE("bicycle without noise turns the front wheel about the ICR (hand-computed pose)", "[bicycle]") {
  BicycleParams p;
  p.frame_length = 1.0f;
  p.dt = 1.0f;
  // l = 1 m, a = 30 deg, v = 1 m/s, dt = 1 s: ICR at (-1, sqrt(3)), turn 0.5 rad; by hand (0.707972, 0.691459, 0.5).
  const Pose2 x = BicycleMotionModel::predict({0.0f, 0.0f, 0.0f}, {1.0f, static_cast<float>(30.0 * kDeg)}, p);
  CHECK(x.x == Approx(0.7079720).margin(2e-6));
  CHECK(x.y == Approx(0.6914588).margin(2e-6));
  CHECK(x.theta == Approx(0.5).margin(1e-6));
  // Straight: a = 0 moves v dt along the heading.
  p.dt = 0.5f;
  const Pose2 s = BicycleMotionModel::predict({1.0f, 2.0f, 0.5f}, {2.0f, 0.0f}, p);
  CHECK(s.x == Approx(1.0 + std::cos(0.5)).margin(1e-6));
  CHECK(s.y == Approx(2.0 + std::sin(0.5)).margin(1e-6));
  CHECK(s.theta == 0.5f);
}

TEST_CASE("bicycle without noise matches the ICR construction over a grid of controls", "[bicycle]") {
  BicycleParams p;
  p.frame_length = 0.7f;
  double worst = 0.0;
  for (double a_deg : {-80.0, -45.0, -10.0, -0.5, 0.0, 0.5, 10.0, 45.0, 80.0})
    for (double v : {-1.5, -0.2, 0.3, 2.0})
      for (double th : {-2.5, 0.0, 1.0})
        for (double dt : {0.01, 0.5, 1.5}) {
          const double a = a_deg * kDeg;
          const BicycleControl u{static_cast<float>(v), static_cast<float>(a)};
          p.dt = static_cast<float>(dt);
          const Pose2 x0{0.3f, -0.2f, static_cast<float>(th)};
          const Pose2 x = BicycleMotionModel::predict(x0, u, p);
          const auto r = icr_reference(x0.x, x0.y, x0.theta, u.v, u.steer, p.dt, p.frame_length);
          const auto q = dv(x);
          worst = std::max({worst, std::fabs(q[0] - r[0]), std::fabs(q[1] - r[1]), std::fabs(wrap(q[2] - r[2]))});
        }
  INFO("worst deviation " << worst);
  CHECK(worst < 1e-5);  // float rounding on poses within 3 m of the origin
}

TEST_CASE("bicycle steering near zero is continuous with the straight line", "[bicycle]") {
  BicycleParams p;
  p.frame_length = 1.0f;
  p.dt = 1.0f;
  const Pose2 x0{0.0f, 0.0f, 0.2f};
  // Across the chord form's series switch (h = 0.1, here at a = asin(0.2) with s = 1) and down to 1e-30 rad. The
  // ICR construction cancels catastrophically for tiny a even in double, so the reference is the arc's closed form
  // in double with libm's sin(h) / h.
  const auto arc_reference = [](double th, double v, double a, double dt, double l) {
    const double s = v * dt, h = 0.5 * s * std::sin(a) / l;
    const double chord = h == 0.0 ? s : s * std::sin(h) / h;
    return std::array<double, 3>{chord * std::cos(th + a + h), chord * std::sin(th + a + h), th + 2.0 * h};
  };
  for (double a : {1e-30, 1e-12, 1e-7, 1e-4, 1e-2, 0.2013579, 0.2013580, 0.5}) {
    for (double sign : {-1.0, 1.0}) {
      const BicycleControl u{1.0f, static_cast<float>(sign * a)};
      const Pose2 x = BicycleMotionModel::predict(x0, u, p);
      const auto r = arc_reference(x0.theta, u.v, u.steer, p.dt, p.frame_length);
      INFO("a = " << sign * a);
      const auto q = dv(x);
      CHECK(std::fabs(q[0] - r[0]) < 2e-6);
      CHECK(std::fabs(q[1] - r[1]) < 2e-6);
      CHECK(std::fabs(q[2] - r[2]) < 2e-6);
    }
  }
  const Pose2 zero = BicycleMotionModel::predict(x0, {1.0f, 0.0f}, p);
  const Pose2 tiny = BicycleMotionModel::predict(x0, {1.0f, 1e-30f}, p);
  CHECK(zero.x == tiny.x);
  CHECK(zero.y == tiny.y);
}

TEST_CASE("bicycle sample without noise equals predict, bit for bit", "[bicycle]") {
  BicycleParams p;
  est::Rng rng(5u);
  for (float a : {-1.2f, 0.0f, 0.3f}) {
    const BicycleControl u{0.8f, a};
    const Pose2 s = BicycleMotionModel::sample({1.0f, 1.0f, 1.0f}, u, p, rng);
    const Pose2 e = BicycleMotionModel::predict({1.0f, 1.0f, 1.0f}, u, p);
    CHECK(std::memcmp(&s, &e, sizeof s) == 0);
  }
}

TEST_CASE("bicycle check rejects bad input and clamps steering beyond the stop", "[bicycle]") {
  const BicycleParams p = noisy_params();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, p) == MotionStatus::ok);
  CHECK(BicycleMotionModel::check({nan, 0.1f}, p) == MotionStatus::rejected_nonfinite);
  CHECK(BicycleMotionModel::check({1.0f, inf}, p) == MotionStatus::rejected_nonfinite);
  BicycleParams bad = p;
  bad.dt = nan;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_nonfinite);
  bad.dt = 0.0f;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_range);
  bad.dt = -0.1f;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_range);
  // 85 deg with an 80 deg stop: clamped (the exercise's case 5); 100 deg is not a steering angle.
  CHECK(BicycleMotionModel::check({1.0f, static_cast<float>(85.0 * kDeg)}, p) == MotionStatus::clamped);
  CHECK(BicycleMotionModel::check({1.0f, static_cast<float>(-85.0 * kDeg)}, p) == MotionStatus::clamped);
  CHECK(BicycleMotionModel::check({1.0f, static_cast<float>(100.0 * kDeg)}, p) == MotionStatus::rejected_range);
  CHECK(BicycleMotionModel::check({1.0f, 85.0f}, p) == MotionStatus::rejected_range);  // degrees as radians
  bad = p;
  bad.frame_length = 0.0f;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.steer_max = static_cast<float>(95.0 * kDeg);
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.speed_var_per_speed = -1.0f;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_range);
  bad = p;
  bad.final_rot_sigma = nan;
  CHECK(BicycleMotionModel::check({1.0f, 0.1f}, bad) == MotionStatus::rejected_nonfinite);

  // Clamped: exactly the motion at the stop, in predict, sample and likelihood.
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const BicycleControl over{0.9f, static_cast<float>(85.0 * kDeg)};
  const BicycleControl at{0.9f, p.steer_max};
  const Pose2 a = BicycleMotionModel::predict(x0, over, p), b = BicycleMotionModel::predict(x0, at, p);
  CHECK(std::memcmp(&a, &b, sizeof a) == 0);
  est::Rng r1(3u), r2(3u);
  const Pose2 sa = BicycleMotionModel::sample(x0, over, p, r1), sb = BicycleMotionModel::sample(x0, at, p, r2);
  CHECK(std::memcmp(&sa, &sb, sizeof sa) == 0);
  CHECK(BicycleMotionModel::likelihood(sa, over, x0, p) == BicycleMotionModel::likelihood(sa, at, x0, p));

  // Rejected: the pose is left as it was, nothing is drawn, the likelihood is zero, never NaN.
  est::Rng r3(9u);
  const est::Rng before = r3;
  const Pose2 kept = BicycleMotionModel::sample({1.0f, 2.0f, 3.0f}, {nan, 0.0f}, p, r3);
  CHECK(kept.x == 1.0f);
  CHECK(kept.y == 2.0f);
  CHECK(kept.theta == 3.0f);
  CHECK(r3 == before);
  BicycleParams no_dt = p;
  no_dt.dt = -1.0f;
  CHECK(BicycleMotionModel::predict({1.0f, 2.0f, 3.0f}, {1.0f, 0.0f}, no_dt).x == 1.0f);
  CHECK(BicycleMotionModel::likelihood({1.0f, 0.0f, 0.0f}, {1.0f, 0.0f}, x0, no_dt) == 0.0f);
  CHECK(BicycleMotionModel::log_likelihood({1.0f, 0.0f, 0.0f}, {nan, 0.0f}, x0, p) == est::motion_density::kLogZero);
}

TEST_CASE("bicycle noisy steering never passes the stop", "[bicycle]") {
  BicycleParams p;
  p.frame_length = 1.0f;
  p.steer_max = static_cast<float>(80.0 * kDeg);
  p.steer_sigma = static_cast<float>(5.0 * kDeg);
  p.dt = 1.0f;
  // Speed and final rotation exact, so the heading change v dt sin(a) / l reveals the steering angle drawn.
  est::Rng rng(11u);
  const BicycleControl u{1.0f, static_cast<float>(85.0 * kDeg)};
  double max_turn = 0.0;
  int near_stop = 0;
  for (int i = 0; i < 20000; ++i) {
    const Pose2 s = BicycleMotionModel::sample({0.0f, 0.0f, 0.0f}, u, p, rng);
    max_turn = std::max(max_turn, static_cast<double>(s.theta));
    if (static_cast<double>(s.theta) > std::sin(78.0 * kDeg)) ++near_stop;
  }
  CHECK(max_turn <= std::sin(80.0 * kDeg) + 1e-6);
  // At the stop with the fold, P(a > 78 deg) = 2 (Phi(0) - Phi(-0.4)) = 0.311: 6223 of 20000, sd 65.
  CHECK(near_stop == Approx(6223).margin(5 * 65));
}

TEST_CASE("bicycle likelihood agrees with the sample histogram (chi-square, alpha = 0.001)", "[bicycle][density]") {
  struct Case {
    const char* name;
    BicycleControl u;
    Pose2 x0;
    double l;
  };
  const Case cases[] = {
      {"a = 25 deg, v = 1 m/s", {1.0f, static_cast<float>(25.0 * kDeg)}, {0.5f, -0.3f, 0.4f}, 1.0},
      {"a = -8 deg, backwards", {-0.8f, static_cast<float>(-8.0 * kDeg)}, {0.0f, 0.0f, -1.0f}, 1.0},
      {"a = 78 deg at the 80 deg stop (fold)", {0.5f, static_cast<float>(78.0 * kDeg)}, {0.0f, 0.0f, 0.0f}, 0.5},
  };
  for (const Case& c : cases) {
    BicycleParams p = noisy_params();
    p.frame_length = static_cast<float>(c.l);
    const auto samples = draw(c.x0, c.u, p, 100000, 77u);
    const auto box = est::test::box_around(samples, {8, 8, 6});
    const auto f = [&](double x, double y, double t) {
      return static_cast<double>(BicycleMotionModel::likelihood(
          {static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, c.u, c.x0, p));
    };
    const auto r = est::test::compare_pose_density(samples, f, box, 0.001);
    INFO(c.name << ": chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV "
                << r.total_variation << " mass in box " << r.mass_in_box);
    CHECK(r.chi2 < r.critical);
    CHECK(r.total_variation < 0.02);  // sampling noise alone gives about 0.009 here
  }
}

TEST_CASE("bicycle likelihood matches the samples when the speed noise exceeds the speed (exercise case 1)",
          "[bicycle][density]") {
  // l = 1 m, a = 25 deg, v = 0.2 m/s with Var(v) = 0.5 |v|: sd 0.32 m/s, so a quarter of the samples move backwards
  // and the start point, where every steering angle ends for v_hat = 0, is a 1/r singularity of the density. Away
  // from it, the mass ahead (x > 5 cm) and behind (x < -5 cm) must equal the samples' fractions.
  BicycleParams p = noisy_params();
  p.speed_var_per_speed = 0.5f;
  p.final_rot_sigma = 0.05f;
  const BicycleControl u{0.2f, static_cast<float>(25.0 * kDeg)};
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const int n = 200000;
  const auto samples = draw(x0, u, p, n, 31u);
  const auto f = [&](double x, double y, double t) {
    return static_cast<double>(
        BicycleMotionModel::likelihood({static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, u, x0, p));
  };
  // The box: the samples' extent plus 10 % on each side (the mass beyond is below the test's resolution).
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const auto& q : samples)
    for (std::size_t d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], q[d]);
      hi[d] = std::max(hi[d], q[d]);
    }
  for (std::size_t d = 0; d < 3; ++d) {
    const double w = hi[d] - lo[d];
    lo[d] -= 0.1 * w;
    hi[d] += 0.1 * w;
  }
  for (int side = 0; side < 2; ++side) {
    std::array<double, 3> box_lo = lo, box_hi = hi;
    (side == 0 ? box_lo[0] : box_hi[0]) = side == 0 ? 0.05 : -0.05;
    double frac = 0.0;
    for (const auto& q : samples) frac += (q[0] >= box_lo[0] && q[0] < box_hi[0]) ? 1.0 : 0.0;
    frac /= n;
    const double mass = est::test::integrate_grid(f, box_lo, box_hi, 5, 1e-6, 3);
    const double se = std::sqrt(frac * (1.0 - frac) / n);
    INFO((side == 0 ? "ahead" : "behind") << ": samples " << frac << " integral " << mass << " se " << se);
    CHECK(std::fabs(mass - frac) < 4.0 * se + 1.3e-4);  // 4 sigma plus the quadrature tolerance (125 x 1e-6)
  }
}

TEST_CASE("bicycle likelihood integrates to one", "[bicycle][density]") {
  BicycleParams p = noisy_params();
  const BicycleControl u{1.0f, static_cast<float>(40.0 * kDeg)};
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const auto samples = draw(x0, u, p, 20000, 5u);
  auto box = est::test::box_around(samples, {1, 1, 1});
  for (std::size_t d = 0; d < 3; ++d) {  // +-7 std: the mass outside is below 1e-6
    const double mid = 0.5 * (box.lo[d] + box.hi[d]), half = 0.5 * (box.hi[d] - box.lo[d]);
    box.lo[d] = mid - 1.75 * half;
    box.hi[d] = mid + 1.75 * half;
  }
  const auto f = [&](double x, double y, double t) {
    return static_cast<double>(
        BicycleMotionModel::likelihood({static_cast<float>(x), static_cast<float>(y), static_cast<float>(t)}, u, x0, p));
  };
  const double mass = est::test::integrate_grid(f, box.lo, box.hi, 6, 1e-6, 3);
  INFO("integral - 1 = " << mass - 1.0);
  // 216 cells refined to 1e-6 each bound the quadrature error by 2.2e-4; measured |1 - integral| < 2e-7.
  CHECK(mass == Approx(1.0).margin(5e-4));
}

TEST_CASE("bicycle Jacobians match central differences", "[bicycle][jacobian]") {
  BicycleParams p = noisy_params();
  p.frame_length = 0.8f;
  p.dt = 0.5f;
  for (float a : {-0.9f, -0.1f, 0.0f, 1e-6f, 0.4f, 1.3f}) {
    for (float v : {-1.0f, 0.5f, 2.0f}) {
      const Pose2 x0{0.2f, -0.4f, 0.7f};
      const BicycleControl u{v, a};
      const auto j = BicycleMotionModel::jacobians(x0, u, p);
      const float e = 1e-3f;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3f dp = Eigen::Vector3f::Zero();
        dp(k) = e;
        const Eigen::Vector3f fd = (BicycleMotionModel::predict(Pose2::from_vector(x0.vector() + dp), u, p).vector() -
                                    BicycleMotionModel::predict(Pose2::from_vector(x0.vector() - dp), u, p).vector()) /
                                   (2.0f * e);
        for (int r = 0; r < 3; ++r) CHECK(j.G(r, k) == Approx(fd(r)).margin(5e-4));
      }
      const BicycleControl uv_p{v + e, a}, uv_m{v - e, a}, ua_p{v, a + e}, ua_m{v, a - e};
      const Eigen::Vector3f fv =
          (BicycleMotionModel::predict(x0, uv_p, p).vector() - BicycleMotionModel::predict(x0, uv_m, p).vector()) / (2.0f * e);
      const Eigen::Vector3f fa =
          (BicycleMotionModel::predict(x0, ua_p, p).vector() - BicycleMotionModel::predict(x0, ua_m, p).vector()) / (2.0f * e);
      for (int r = 0; r < 3; ++r) {
        INFO("a " << a << " v " << v << " row " << r);
        CHECK(j.V(r, 0) == Approx(fv(r)).margin(5e-4));
        CHECK(j.V(r, 1) == Approx(fa(r)).margin(5e-4));
      }
      CHECK(j.M(0, 0) == Approx(p.speed_var_per_speed * std::fabs(v)));
      CHECK(j.M(1, 1) == Approx(p.steer_sigma * p.steer_sigma));
      CHECK(j.M(0, 1) == 0.0f);
    }
  }
}

TEST_CASE("bicycle sampling with the same seed gives the same bits", "[bicycle]") {
  const BicycleParams p = noisy_params();
  const BicycleControl u{0.7f, 0.3f};
  const auto a = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 42u);
  const auto b = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 42u);
  const auto c = draw({0.0f, 0.0f, 0.0f}, u, p, 1000, 43u);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof a[0]) != 0);
}
