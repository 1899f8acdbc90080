#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "est/filter/log_weights.hpp"

TEST_CASE("log-sum-exp normalization survives weights far below float's range", "[weights]") {
  // exp(-1000) underflows float; the normalized weights must still be 1/3 each and 2/3 + 1/3 for the pair.
  std::vector<float> lw = {-1000.0f, -1000.0f, -1000.0f};
  const auto r = est::normalize_log_weights(lw.data(), 3u);
  CHECK_FALSE(r.degenerate);
  CHECK(r.log_sum == Approx(-1000.0 + std::log(3.0)).margin(1e-3));
  for (float v : lw) CHECK(std::exp(static_cast<double>(v)) == Approx(1.0 / 3.0).epsilon(1e-5));
  // About 2:1, as far as float can say it at -2000 (spacing 1.2e-4): the reference uses the stored inputs.
  std::vector<float> two = {-2000.0f, -2000.0f - std::log(2.0f)};
  const double d = static_cast<double>(two[1]) - static_cast<double>(two[0]);
  est::normalize_log_weights(two.data(), 2u);
  CHECK(std::exp(static_cast<double>(two[0])) == Approx(1.0 / (1.0 + std::exp(d))).epsilon(1e-6));
}

TEST_CASE("all-zero or NaN weights are degenerate and become uniform, never NaN", "[weights]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> lw = {-inf, nan, -inf, nan};
  const auto r = est::normalize_log_weights(lw.data(), 4u);
  CHECK(r.degenerate);
  CHECK(r.nonfinite == 2u);
  for (float v : lw) CHECK(v == Approx(-std::log(4.0)));
}

TEST_CASE("a +inf or NaN weight counts as zero weight, not as certainty", "[weights]") {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> lw = {inf, 0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f};
  const auto r = est::normalize_log_weights(lw.data(), 4u);
  CHECK_FALSE(r.degenerate);
  CHECK(r.nonfinite == 2u);
  CHECK(std::exp(static_cast<double>(lw[1])) == Approx(0.5).epsilon(1e-6));
  CHECK(std::exp(static_cast<double>(lw[0])) == 0.0);
}

TEST_CASE("effective sample size is N for equal weights and 1 for a single particle", "[weights]") {
  std::vector<float> lw(100, 0.0f);
  est::normalize_log_weights(lw.data(), 100u);
  CHECK(est::effective_sample_size(lw.data(), 100u) == Approx(100.0f).epsilon(1e-4));
  std::vector<float> one(100, -1e6f);
  one[17] = 0.0f;
  est::normalize_log_weights(one.data(), 100u);
  CHECK(est::effective_sample_size(one.data(), 100u) == Approx(1.0f).epsilon(1e-6));
  // Two equal halves: ESS = 2 exactly.
  std::vector<float> half(10, -1e6f);
  half[2] = half[7] = 0.0f;
  est::normalize_log_weights(half.data(), 10u);
  CHECK(est::effective_sample_size(half.data(), 10u) == Approx(2.0f).epsilon(1e-6));
}
