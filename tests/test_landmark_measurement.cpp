#include <catch2/catch.hpp>

#include <cmath>

#include "est/filter/landmark_measurement.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

// Central differences in double around float evaluations: step 1e-3, so the truncation error (~h^2 f''') and the
// float rounding (~1e-7 / h) are both below 1e-3 for the geometries drawn (ranges 0.5-10 m).
constexpr double kStep = 1.0e-3;
constexpr double kTol = 2.0e-3;

Eigen::Vector3f random_pose(est::Rng& rng) {
  return {rng.uniform(-5.0f, 5.0f), rng.uniform(-5.0f, 5.0f), rng.uniform(-3.0f, 3.0f)};
}
Eigen::Vector2f random_point_away(est::Rng& rng, const Eigen::Vector2f& from) {
  for (;;) {
    const Eigen::Vector2f p(rng.uniform(-5.0f, 5.0f), rng.uniform(-5.0f, 5.0f));
    if ((p - from).norm() > 0.5f) return p;
  }
}
double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

}  // namespace

TEST_CASE("range Jacobians match central differences", "[landmark_measurement]") {
  est::Rng rng(11u);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector2f a(rng.uniform(-5.0f, 5.0f), rng.uniform(-5.0f, 5.0f));
    const Eigen::Vector2f b = random_point_away(rng, a);
    const est::RangeMeasurement h = est::range_measurement(a, b);
    REQUIRE(h.ok);
    CHECK(h.range == Approx((b - a).norm()).epsilon(1e-6));
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2f ap = a, am = a, bp = b, bm = b;
      ap(i) += static_cast<float>(kStep);
      am(i) -= static_cast<float>(kStep);
      bp(i) += static_cast<float>(kStep);
      bm(i) -= static_cast<float>(kStep);
      const double da = (static_cast<double>(est::range_measurement(ap, b).range) -
                         static_cast<double>(est::range_measurement(am, b).range)) / (2 * kStep);
      const double db = (static_cast<double>(est::range_measurement(a, bp).range) -
                         static_cast<double>(est::range_measurement(a, bm).range)) / (2 * kStep);
      CHECK(static_cast<double>(h.d_a(i)) == Approx(da).margin(kTol));
      CHECK(static_cast<double>(h.d_b(i)) == Approx(db).margin(kTol));
    }
  }
}

TEST_CASE("range/bearing Jacobians (pose and point robot) match central differences", "[landmark_measurement]") {
  est::Rng rng(12u);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3f x = random_pose(rng);
    const Eigen::Vector2f m = random_point_away(rng, x.head<2>());
    const auto h = est::range_bearing_measurement<3>(x, m);
    REQUIRE(h.ok);
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3f xp = x, xm = x;
      xp(i) += static_cast<float>(kStep);
      xm(i) -= static_cast<float>(kStep);
      const auto hp = est::range_bearing_measurement<3>(xp, m), hm = est::range_bearing_measurement<3>(xm, m);
      CHECK(static_cast<double>(h.H_robot(0, i)) ==
            Approx((static_cast<double>(hp.z(0)) - static_cast<double>(hm.z(0))) / (2 * kStep)).margin(kTol));
      CHECK(static_cast<double>(h.H_robot(1, i)) ==
            Approx(wrap(static_cast<double>(hp.z(1)) - static_cast<double>(hm.z(1))) / (2 * kStep)).margin(kTol));
    }
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2f mp = m, mm = m;
      mp(i) += static_cast<float>(kStep);
      mm(i) -= static_cast<float>(kStep);
      const auto hp = est::range_bearing_measurement<3>(x, mp), hm = est::range_bearing_measurement<3>(x, mm);
      CHECK(static_cast<double>(h.H_landmark(0, i)) ==
            Approx((static_cast<double>(hp.z(0)) - static_cast<double>(hm.z(0))) / (2 * kStep)).margin(kTol));
      CHECK(static_cast<double>(h.H_landmark(1, i)) ==
            Approx(wrap(static_cast<double>(hp.z(1)) - static_cast<double>(hm.z(1))) / (2 * kStep)).margin(kTol));
    }
    // The point robot sees world-frame bearings: the same as a pose robot with heading 0.
    const Eigen::Vector2f p = x.head<2>();
    const auto h2 = est::range_bearing_measurement<2>(p, m);
    const auto h0 = est::range_bearing_measurement<3>(Eigen::Vector3f(x(0), x(1), 0.0f), m);
    CHECK(h2.z == h0.z);
    CHECK(h2.H_robot == h0.H_robot.leftCols<2>());
  }
}

TEST_CASE("the inverse measurement places the landmark back, and its Jacobians match central differences",
          "[landmark_measurement]") {
  est::Rng rng(13u);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3f x = random_pose(rng);
    const Eigen::Vector2f m = random_point_away(rng, x.head<2>());
    const auto h = est::range_bearing_measurement<3>(x, m);
    const auto g = est::landmark_from_range_bearing<3>(x, h.z);
    CHECK((g.m - m).norm() < 1e-4f);
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3f xp = x, xm = x;
      xp(i) += static_cast<float>(kStep);
      xm(i) -= static_cast<float>(kStep);
      const Eigen::Vector2f d =
          (est::landmark_from_range_bearing<3>(xp, h.z).m - est::landmark_from_range_bearing<3>(xm, h.z).m);
      for (int r = 0; r < 2; ++r)
        CHECK(static_cast<double>(g.G_robot(r, i)) == Approx(static_cast<double>(d(r)) / (2 * kStep)).margin(kTol));
    }
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2f zp = h.z, zm = h.z;
      zp(i) += static_cast<float>(kStep);
      zm(i) -= static_cast<float>(kStep);
      const Eigen::Vector2f d =
          (est::landmark_from_range_bearing<3>(x, zp).m - est::landmark_from_range_bearing<3>(x, zm).m);
      for (int r = 0; r < 2; ++r)
        CHECK(static_cast<double>(g.G_z(r, i)) == Approx(static_cast<double>(d(r)) / (2 * kStep)).margin(kTol));
    }
  }
}

TEST_CASE("a landmark on top of the robot is refused, not differentiated", "[landmark_measurement]") {
  const Eigen::Vector2f a(1.0f, 2.0f);
  CHECK_FALSE(est::range_measurement(a, a).ok);
  CHECK_FALSE(est::range_bearing_measurement<3>(Eigen::Vector3f(1.0f, 2.0f, 0.3f), a).ok);
  CHECK_FALSE(est::range_measurement(a, Eigen::Vector2f(std::nanf(""), 0.0f)).ok);
}
