#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "est/sensor/landmark_model.hpp"
#include "statistics.hpp"

namespace {

est::LandmarkMapStorage<8> g_map;

double log_n(double a, double s) { return -0.5 * a * a / (s * s) - std::log(s * std::sqrt(2.0 * M_PI)); }

void three_landmarks() {
  g_map.clear();
  REQUIRE(g_map.add({3.0f, 4.0f, 2.0f}) == est::MapStatus::ok);
  REQUIRE(g_map.add({-2.0f, 1.0f, 5.0f}) == est::MapStatus::ok);
  REQUIRE(g_map.add({0.0f, -6.0f, 7.0f}) == est::MapStatus::ok);
}

}  // namespace

TEST_CASE("landmark model log-likelihood matches the hand computation of table 6.4", "[landmark_model]") {
  three_landmarks();
  const est::LandmarkNoise n{0.1f, 0.05f, 0.5f};
  const est::Pose2 x{0.0f, 0.0f, 0.0f};
  const est::LandmarkMeasurement f{5.1f, 0.95f, 2.3f};
  // r* = 5, phi* = atan2(4, 3), s* = 2.
  const double ref = log_n(0.1, 0.1) + log_n(0.95 - std::atan2(4.0, 3.0), 0.05) + log_n(0.3, 0.5);
  CHECK(double(est::landmark_model_known_correspondence(f, 0, x, g_map.view(), n)) == Approx(ref).margin(2e-4));
  // Bearing errors wrap: measuring pi - 0.01 when pi + 0.01 (= -pi + 0.01) is expected is a 0.02 rad error.
  g_map.clear();
  REQUIRE(g_map.add({-10.0f, 0.1f, 0.0f}) == est::MapStatus::ok);
  const est::LandmarkNoise nb{0.1f, 0.05f, 0.0f};  // no signature factor
  const float phi_star = std::atan2(0.1f, -10.0f);
  const est::LandmarkMeasurement g{std::hypot(10.0f, 0.1f), phi_star - 0.02f, 123.0f};
  CHECK(double(est::landmark_model_known_correspondence(g, 0, x, g_map.view(), nb)) ==
        Approx(log_n(0.0, 0.1) + log_n(0.02, 0.05)).margin(2e-3));
}

TEST_CASE("landmark model integrates to one over range and bearing", "[landmark_model]") {
  three_landmarks();
  const est::LandmarkNoise n{0.2f, 0.1f, 0.0f};
  const est::Pose2 x{0.5f, -0.5f, 0.4f};
  const est::LandmarkMeasurement e = est::expected_landmark_measurement(x, g_map.view()[1]);
  // Midpoint rule over r in r* +- 8 sigma and phi over the whole circle (-pi, pi]; tolerance 1e-3.
  const int nr = 400, nb = 2000;
  const double r0 = double(e.range) - 1.6, hr = 3.2 / nr, hb = 2.0 * M_PI / nb;
  double sum = 0.0;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nb; ++j) {
      const est::LandmarkMeasurement f{static_cast<float>(r0 + (i + 0.5) * hr), static_cast<float>(-M_PI + (j + 0.5) * hb),
                                       0.0f};
      sum += std::exp(double(est::landmark_model_known_correspondence(f, 1, x, g_map.view(), n))) * hr * hb;
    }
  CHECK(sum == Approx(1.0).margin(1e-3));
}

TEST_CASE("invalid landmark measurements give the floor, never NaN", "[landmark_model]") {
  three_landmarks();
  const est::LandmarkNoise n{0.1f, 0.05f, 0.0f};
  const est::Pose2 x{0.0f, 0.0f, 0.0f};
  const float nan = __builtin_nanf("");
  CHECK(est::check_landmark_measurement({1.0f, 0.0f, 0.0f}, 3, g_map.view(), n) == est::LandmarkStatus::bad_correspondence);
  CHECK(est::check_landmark_measurement({1.0f, 0.0f, 0.0f}, -1, g_map.view(), n) == est::LandmarkStatus::bad_correspondence);
  CHECK(est::check_landmark_measurement({nan, 0.0f, 0.0f}, 0, g_map.view(), n) == est::LandmarkStatus::nonfinite);
  CHECK(est::check_landmark_measurement({-1.0f, 0.0f, 0.0f}, 0, g_map.view(), n) == est::LandmarkStatus::negative_range);
  CHECK(est::check_landmark_measurement({1.0f, 0.0f, 0.0f}, 0, g_map.view(), {0.0f, 0.1f, 0.0f}) ==
        est::LandmarkStatus::bad_noise);
  CHECK(est::landmark_model_known_correspondence({nan, 0.0f, 0.0f}, 0, x, g_map.view(), n) == est::kLandmarkLogDensityFloor);
  CHECK(est::landmark_model_known_correspondence({5.0f, 0.9f, 0.0f}, 0, {nan, 0.0f, 0.0f}, g_map.view(), n) ==
        est::kLandmarkLogDensityFloor);
  // A far outlier is floored, not -inf.
  CHECK(est::landmark_model_known_correspondence({500.0f, 0.9f, 0.0f}, 0, x, g_map.view(), n) == est::kLandmarkLogDensityFloor);
}

TEST_CASE("sampled landmark measurements have the model's mean and spread", "[landmark_model]") {
  three_landmarks();
  const est::LandmarkNoise n{0.2f, 0.05f, 0.3f};
  const est::Pose2 x{1.0f, 1.0f, 2.5f};
  const est::Landmark& l = g_map.view()[2];
  const est::LandmarkMeasurement e = est::expected_landmark_measurement(x, l);
  est::Rng rng(77u);
  const std::size_t N = 20000;
  std::vector<double> r(N), b(N), s(N);
  for (std::size_t i = 0; i < N; ++i) {
    const est::LandmarkMeasurement f = est::sample_landmark_measurement(x, l, n, rng);
    r[i] = f.range;
    b[i] = est::fmath::normalize_angle(f.bearing - e.bearing);
    s[i] = f.signature;
  }
  // Means within 4 standard errors, variances within 4 standard errors of the sample variance (normal: kurtosis 0).
  const auto mr = est::test::moments(r), mb = est::test::moments(b), ms = est::test::moments(s);
  CHECK(std::fabs(mr.mean - double(e.range)) < 4.0 * est::test::mean_standard_error(0.04, N));
  CHECK(std::fabs(mb.mean) < 4.0 * est::test::mean_standard_error(0.0025, N));
  CHECK(std::fabs(ms.mean - double(l.signature)) < 4.0 * est::test::mean_standard_error(0.09, N));
  CHECK(std::fabs(mr.variance - 0.04) < 4.0 * est::test::variance_standard_error(0.04, 0.0, N));
  CHECK(std::fabs(mb.variance - 0.0025) < 4.0 * est::test::variance_standard_error(0.0025, 0.0, N));
}

TEST_CASE("poses sampled from one landmark sighting (table 6.5) reproduce the sighting", "[landmark_model]") {
  three_landmarks();
  const est::Landmark& l = g_map.view()[0];
  const est::LandmarkMeasurement f{2.5f, -0.7f, 0.0f};
  const est::LandmarkNoise tiny{1e-6f, 1e-6f, 0.0f};
  est::Rng rng(8u);
  for (int i = 0; i < 200; ++i) {
    const est::Pose2 p = est::sample_landmark_model_known_correspondence(f, l, tiny, rng);
    const est::LandmarkMeasurement g = est::expected_landmark_measurement(p, l);
    CHECK(g.range == Approx(2.5f).margin(1e-4));
    CHECK(est::fmath::normalize_angle(g.bearing - f.bearing) == Approx(0.0f).margin(1e-4));
  }
}

TEST_CASE("two identified landmarks give the pose exactly without noise", "[landmark_model]") {
  est::Rng rng(21u);
  for (int i = 0; i < 1000; ++i) {
    const est::Landmark l1{rng.uniform(-10.0f, 10.0f), rng.uniform(-10.0f, 10.0f), 1.0f};
    const est::Landmark l2{rng.uniform(-10.0f, 10.0f), rng.uniform(-10.0f, 10.0f), 2.0f};
    if (std::hypot(l1.x - l2.x, l1.y - l2.y) < 1.0f) continue;
    const est::Pose2 x{rng.uniform(-10.0f, 10.0f), rng.uniform(-10.0f, 10.0f), rng.uniform(-est::kPi, est::kPi)};
    const est::TwoLandmarkPose p = est::pose_from_two_landmarks(l1, est::expected_landmark_measurement(x, l1), l2,
                                                                est::expected_landmark_measurement(x, l2));
    REQUIRE(p.status == est::TwoLandmarkStatus::ok);
    // Float round-off only (coordinates up to 10 m, ranges up to 28 m).
    CHECK(p.pose.x == Approx(x.x).margin(2e-4));
    CHECK(p.pose.y == Approx(x.y).margin(2e-4));
    CHECK(est::fmath::normalize_angle(p.pose.theta - x.theta) == Approx(0.0f).margin(2e-5));
    CHECK(p.separation_mismatch < 1e-4f);
  }
}

TEST_CASE("two-landmark pose reports degenerate and inconsistent geometry", "[landmark_model]") {
  const est::Landmark l1{1.0f, 1.0f, 1.0f}, l2{1.0f, 1.0f, 2.0f}, l3{4.0f, 5.0f, 3.0f};
  const est::Pose2 x{0.0f, 0.0f, 0.3f};
  const auto f1 = est::expected_landmark_measurement(x, l1);
  const auto f3 = est::expected_landmark_measurement(x, l3);
  CHECK(est::pose_from_two_landmarks(l1, f1, l2, f1).status == est::TwoLandmarkStatus::degenerate_landmarks);
  CHECK(est::pose_from_two_landmarks(l1, f1, l3, f1).status == est::TwoLandmarkStatus::degenerate_measurement);
  est::LandmarkMeasurement wrong = f3;
  wrong.range += 1.0f;
  const auto p = est::pose_from_two_landmarks(l1, f1, l3, wrong, 0.05f, 0.5f);
  CHECK(p.status == est::TwoLandmarkStatus::inconsistent);
  CHECK(p.separation_mismatch > 0.5f);
  est::LandmarkMeasurement nan = f3;
  nan.bearing = __builtin_nanf("");
  CHECK(est::pose_from_two_landmarks(l1, f1, l3, nan).status == est::TwoLandmarkStatus::nonfinite);
}
