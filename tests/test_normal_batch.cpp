#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "est/random/normal_batch.hpp"
#include "statistics.hpp"

TEST_CASE("bulk normal draws pass KS against N(0, 1), have its moments and its tails", "[normal_batch]") {
  est::Rng rng(31u);
  const std::uint32_t n = 400001;
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
  // Consecutive values (consecutive uniforms) are independent: their correlation is 0 within 4 / sqrt(n / 2).
  double sxy = 0.0;
  for (std::uint32_t i = 0; i + 1 < n; i += 2) sxy += x[i] * x[i + 1];
  CHECK(std::fabs(sxy / (n / 2)) < 4.0 / std::sqrt(n / 2.0));
  // The tails (the formula beyond the table): the mass beyond 2 and 3 sigma within 4 standard errors of N(0, 1)'s.
  for (const double t : {2.0, 3.0}) {
    const double p = 2.0 * (1.0 - est::test::normal_cdf(t));
    const double beyond = double(std::count_if(x.begin(), x.end(), [t](double v) { return std::fabs(v) > t; })) / n;
    CHECK(std::fabs(beyond - p) < 4.0 * std::sqrt(p * (1.0 - p) / n));
  }
  // Bounded as stated: 24-bit uniforms cut the tail at 5.42.
  CHECK(std::fabs(*std::max_element(z.begin(), z.end(),
                                    [](float a, float b) { return std::fabs(a) < std::fabs(b); })) <=
        est::kNormalBatchMax);
}

TEST_CASE("bulk normal draws use one uniform per value and repeat bit for bit", "[normal_batch]") {
  est::Rng a(5u), b(5u), c(5u);
  float x[7], y[7];
  est::fill_standard_normals(a, x, 7);
  est::fill_standard_normals(b, y, 7);
  for (int i = 0; i < 7; ++i) CHECK(x[i] == y[i]);
  for (int i = 0; i < 7; ++i) c.next();
  CHECK(a == c);
}

TEST_CASE("bulk normal draws at the extreme uniforms stay within the stated bound and keep their sign",
          "[normal_batch]") {
  // The tail formula's extremes: the smallest and largest 24-bit uniforms.
  const float lo = -est::normal_batch_detail::tail(0u), hi = est::normal_batch_detail::tail(0u);
  CHECK(lo < -5.0f);
  CHECK(hi <= est::kNormalBatchMax);
  // At the table's edges (u = 1/512) the tail formula meets the table within A&S's 4.5e-4.
  CHECK(std::fabs(double(est::normal_batch_detail::tail((1u << 15) - 1u)) - 2.8856349124267571) < 1e-3);
}
