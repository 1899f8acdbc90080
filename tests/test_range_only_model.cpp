#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "est/sensor/range_only_model.hpp"
#include "statistics.hpp"

TEST_CASE("range-only model is the Gaussian of the range error", "[range_only_model]") {
  const est::Pose2 x{1.0f, 2.0f, 0.5f};
  // Target at (4, 6): true range 5.
  const double ref = -0.5 * (0.2 * 0.2) / (0.1 * 0.1) - std::log(0.1 * std::sqrt(2.0 * M_PI));
  CHECK(double(est::range_only_model(5.2f, x, 4.0f, 6.0f, 0.1f)) == Approx(ref).margin(1e-5));
  // Another robot as the target; its heading does not matter.
  CHECK(est::range_only_model(5.2f, x, est::Pose2{4.0f, 6.0f, 2.0f}, 0.1f) == est::range_only_model(5.2f, x, 4.0f, 6.0f, 0.1f));
  // The antenna 0.5 m ahead of the robot centre along heading pi/2: sensor at (1, 2.5), range to (1, 7.5) is 5.
  CHECK(est::expected_range({1.0f, 2.0f, est::kHalfPi}, 1.0f, 7.5f, 0.5f, 0.0f) == Approx(5.0f).margin(1e-5));
}

TEST_CASE("range-only model integrates to one over z", "[range_only_model]") {
  const est::Pose2 x{0.0f, 0.0f, 0.0f};
  const int n = 20000;
  const double h = 2.0 / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    sum += std::exp(double(est::range_only_model(static_cast<float>(2.0 + (i + 0.5) * h), x, 3.0f, 0.0f, 0.1f))) * h;
  CHECK(sum == Approx(1.0).margin(1e-4));
}

TEST_CASE("range-only model gives the floor for invalid input, never NaN", "[range_only_model]") {
  const est::Pose2 x{0.0f, 0.0f, 0.0f};
  const float nan = __builtin_nanf(""), inf = __builtin_inff();
  CHECK(est::range_only_model(nan, x, 1.0f, 0.0f, 0.1f) == est::kRangeOnlyLogDensityFloor);
  CHECK(est::range_only_model(inf, x, 1.0f, 0.0f, 0.1f) == est::kRangeOnlyLogDensityFloor);
  CHECK(est::range_only_model(1.0f, x, 1.0f, 0.0f, 0.0f) == est::kRangeOnlyLogDensityFloor);
  CHECK(est::range_only_model(1.0f, {nan, 0.0f, 0.0f}, 1.0f, 0.0f, 0.1f) == est::kRangeOnlyLogDensityFloor);
  CHECK(est::range_only_model(1000.0f, x, 1.0f, 0.0f, 0.1f) == est::kRangeOnlyLogDensityFloor);
}

TEST_CASE("sampled ranges have the true range as mean and sigma as spread", "[range_only_model]") {
  est::Rng rng(4u);
  const std::size_t N = 20000;
  std::vector<double> z(N);
  for (auto& v : z) v = est::sample_range_only_measurement({0.0f, 0.0f, 0.0f}, 3.0f, 4.0f, 0.3f, rng);
  const auto m = est::test::moments(z);
  CHECK(std::fabs(m.mean - 5.0) < 4.0 * est::test::mean_standard_error(0.09, N));
  CHECK(std::fabs(m.variance - 0.09) < 4.0 * est::test::variance_standard_error(0.09, 0.0, N));
}
