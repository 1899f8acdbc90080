#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "est/random/normal_batch.hpp"
#include "statistics.hpp"

TEST_CASE("bulk normal draws pass KS against N(0, 1) and have its moments", "[normal_batch]") {
  est::Rng rng(31u);
  const std::uint32_t n = 400001;  // odd: the last value is a lone cosine half
  std::vector<float> z(n);
  est::fill_standard_normals(rng, z.data(), n);
  std::vector<double> x(z.begin(), z.end());
  const auto m = est::test::moments(x);
  // 4 standard errors: mean 1/sqrt(n), variance sqrt(2/n), excess kurtosis sqrt(24/n).
  CHECK(std::fabs(m.mean) < 4.0 / std::sqrt(n));
  CHECK(std::fabs(m.variance - 1.0) < 4.0 * std::sqrt(2.0 / n));
  CHECK(std::fabs(m.skewness) < 4.0 * std::sqrt(6.0 / n));
  CHECK(std::fabs(m.excess_kurtosis) < 4.0 * std::sqrt(24.0 / n));
  CHECK(est::test::ks_statistic(x, est::test::normal_cdf) < est::test::ks_critical(x.size(), 0.001));
  // The two halves of a pair are independent: their correlation is 0 within 4 / sqrt(n / 2).
  double sxy = 0.0;
  for (std::uint32_t i = 0; i + 1 < n; i += 2) sxy += x[i] * x[i + 1];
  CHECK(std::fabs(sxy / (n / 2)) < 4.0 / std::sqrt(n / 2.0));
  // Bounded as stated: 24-bit uniforms cut the tail at 5.77.
  CHECK(std::fabs(*std::max_element(z.begin(), z.end(),
                                    [](float a, float b) { return std::fabs(a) < std::fabs(b); })) <= 5.77f);
}

TEST_CASE("bulk normal draws use two uniforms per pair and repeat bit for bit", "[normal_batch]") {
  est::Rng a(5u), b(5u), c(5u);
  float x[7], y[7];
  est::fill_standard_normals(a, x, 7);
  est::fill_standard_normals(b, y, 7);
  for (int i = 0; i < 7; ++i) CHECK(x[i] == y[i]);
  for (int i = 0; i < 8; ++i) c.next();  // 4 pairs
  CHECK(a == c);
}
