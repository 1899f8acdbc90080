#include <catch2/catch.hpp>

#include <cmath>

#include <Eigen/Dense>

#include "est/random/samplers.hpp"
#include "est/slam/range_only_initializer.hpp"
#include "statistics.hpp"

namespace {
using Init = est::RangeOnlyInitializer<2, 8>;
const Eigen::Matrix2f kNoPositionError = Eigen::Matrix2f::Identity() * 1e-8f;
}  // namespace

TEST_CASE("exact ranges from three spread positions give the circles' intersection", "[range_only_initializer]") {
  est::RangeOnlyInitParams p;
  p.min_observations = 3;
  Init init(p);
  const Eigen::Vector2f m(2.0f, 3.0f);
  const Eigen::Vector2f pos[3] = {{0.0f, 0.0f}, {4.0f, 0.0f}, {1.0f, -2.0f}};
  est::RangeOnlyLandmark out;
  CHECK(init.add(5, pos[0], kNoPositionError, (m - pos[0]).norm(), 1e-4f, &out) == est::RangeOnlyInitStatus::pending);
  CHECK(init.add(5, pos[1], kNoPositionError, (m - pos[1]).norm(), 1e-4f, &out) == est::RangeOnlyInitStatus::pending);
  REQUIRE(init.add(5, pos[2], kNoPositionError, (m - pos[2]).norm(), 1e-4f, &out) == est::RangeOnlyInitStatus::ready);
  CHECK((out.mean - m).norm() < 1e-4f);
  CHECK(out.covariance(0, 0) > 0.0f);
  CHECK(out.covariance(0, 0) * out.covariance(1, 1) > out.covariance(0, 1) * out.covariance(1, 0));
  CHECK(init.observations(5) == 0);  // slot freed
}

TEST_CASE("positions on one line leave the mirror ambiguity: the landmark stays pending", "[range_only_initializer]") {
  Init init;
  const Eigen::Vector2f m(2.0f, 3.0f);
  est::RangeOnlyLandmark out;
  for (int k = 0; k < 12; ++k) {
    const Eigen::Vector2f pos(0.5f * static_cast<float>(k), 0.0f);
    CHECK(init.add(1, pos, kNoPositionError, (m - pos).norm(), 1e-4f, &out) == est::RangeOnlyInitStatus::pending);
  }
  CHECK(init.observations(1) == 8);  // bounded: the oldest are dropped
}

TEST_CASE("noisy ranges: the initial estimate is consistent with its covariance (NEES, 200 runs)",
          "[range_only_initializer]") {
  constexpr int kRuns = 200;
  est::Rng rng(3u);
  const Eigen::Vector2f m(2.0f, 3.0f);
  const float sigma = 0.05f, sigma_pos = 0.03f;
  double nees_sum = 0.0;
  int ready = 0;
  for (int run = 0; run < kRuns; ++run) {
    est::RangeOnlyInitParams p;
    p.inflation = 1.0f;  // the robot positions here are independent: the LS covariance is the right one
    Init init(p);
    est::RangeOnlyLandmark out;
    for (int k = 0; k < 8; ++k) {
      const float a = 0.8f * static_cast<float>(k);
      const Eigen::Vector2f truth_pos(1.5f * std::cos(a), 1.5f * std::sin(a));
      const Eigen::Vector2f est_pos =
          truth_pos + Eigen::Vector2f(est::sample_normal(rng, sigma_pos), est::sample_normal(rng, sigma_pos));
      const float z = (m - truth_pos).norm() + est::sample_normal(rng, sigma);
      const auto st =
          init.add(0, est_pos, Eigen::Matrix2f::Identity() * (sigma_pos * sigma_pos), z, sigma * sigma, &out);
      if (st == est::RangeOnlyInitStatus::ready) {
        const Eigen::Vector2d e = (out.mean - m).cast<double>();
        nees_sum += e.dot(out.covariance.cast<double>().inverse() * e);
        ++ready;
        break;
      }
    }
  }
  REQUIRE(ready >= kRuns * 9 / 10);
  const double anees = nees_sum / ready;
  const double lo = est::test::chi_square_critical(2.0 * ready, 0.975) / ready;
  const double hi = est::test::chi_square_critical(2.0 * ready, 0.025) / ready;
  WARN("range-only initialization: " << ready << " of " << kRuns << " ready, ANEES " << anees << " band [" << lo
                                     << ", " << hi << "]");
  CHECK(anees <= hi);
  CHECK(anees >= 0.5 * lo);  // the linearized covariance may be a little pessimistic, never optimistic
}

TEST_CASE("a wrong range makes the fit inconsistent and is not used", "[range_only_initializer]") {
  est::RangeOnlyInitParams p;
  p.min_observations = 5;
  Init init(p);
  const Eigen::Vector2f m(2.0f, 3.0f);
  const Eigen::Vector2f pos[5] = {{0.0f, 0.0f}, {4.0f, 0.0f}, {1.0f, -2.0f}, {3.0f, -1.0f}, {-1.0f, 1.0f}};
  est::RangeOnlyLandmark out;
  for (int k = 0; k < 4; ++k)
    REQUIRE(init.add(2, pos[k], kNoPositionError, (m - pos[k]).norm() + (k == 0 ? 1.0f : 0.0f), 1e-4f, &out) ==
            est::RangeOnlyInitStatus::pending);
  CHECK(init.add(2, pos[4], kNoPositionError, (m - pos[4]).norm(), 1e-4f, &out) ==
        est::RangeOnlyInitStatus::inconsistent);
}

TEST_CASE("bad input is refused and the capacity is bounded", "[range_only_initializer]") {
  Init init;
  est::RangeOnlyLandmark out;
  const Eigen::Vector2f p(0.0f, 0.0f);
  CHECK(init.add(1, p, kNoPositionError, std::nanf(""), 1e-4f, &out) == est::RangeOnlyInitStatus::rejected_input);
  CHECK(init.add(1, p, kNoPositionError, 1.0f, -1.0f, &out) == est::RangeOnlyInitStatus::rejected_input);
  CHECK(init.add(1, p, kNoPositionError, 1.0f, 1e-4f, &out) == est::RangeOnlyInitStatus::pending);
  CHECK(init.add(2, p, kNoPositionError, 1.0f, 1e-4f, &out) == est::RangeOnlyInitStatus::pending);
  CHECK(init.add(3, p, kNoPositionError, 1.0f, 1e-4f, &out) == est::RangeOnlyInitStatus::rejected_capacity);
}
