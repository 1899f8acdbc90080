#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "est/math/log_product.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

double ulp(double y) { return std::ldexp(1.0, std::ilogb(std::fabs(y) > 1e-30 ? y : 1e-30) - 23); }

// The header's bound: n 2^-24 (1 + 2^-23) + 2 ULP of the result.
double bound(int n, double exact) { return n * std::ldexp(1.0, -24) * (1.0 + std::ldexp(1.0, -23)) + 2.0 * ulp(exact); }

}  // namespace

TEST_CASE("log of a product equals the sum of the logs within n 2^-24 + 2 ULP", "[log_product]") {
  est::Rng rng(5u);
  double worst_ratio = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = trial % 4 == 0 ? 60 : 360;
    // Beam-model-like factors: densities from 1e-30 (the floor) to 1e4 per metre, log-uniform.
    est::LogProduct q;
    double exact = 0.0;
    for (int k = 0; k < n; ++k) {
      const float d = std::exp(rng.uniform(-70.0f, 9.2f));
      q.mul(d);
      exact += std::log(double(std::max(d, est::LogProduct::kFactorMin)));
    }
    const double err = std::fabs(double(q.log()) - exact);
    worst_ratio = std::max(worst_ratio, err / bound(n, exact));
    INFO("trial " << trial << " n " << n << " exact " << exact << " error " << err);
    REQUIRE(err <= bound(n, exact));
  }
  std::printf("log product: worst error %.2f of the stated bound\n", worst_ratio);
}

TEST_CASE("log of a product of factors near one keeps the small sum", "[log_product]") {
  // 360 factors 1 +- 1e-3: the sum of logs is O(1e-2); absolute error within the same bound.
  est::Rng rng(6u);
  est::LogProduct q;
  double exact = 0.0;
  for (int k = 0; k < 360; ++k) {
    const float d = 1.0f + rng.uniform(-1e-3f, 1e-3f);
    q.mul(d);
    exact += std::log(double(d));
  }
  CHECK(std::fabs(double(q.log()) - exact) <= bound(360, exact));
}

TEST_CASE("log product floors and caps each factor and never returns NaN", "[log_product]") {
  const float nan = __builtin_nanf(""), inf = __builtin_inff();
  est::LogProduct q;
  CHECK(q.log() == 0.0f);  // the empty product
  q.mul(0.0f);
  q.mul(-3.0f);
  q.mul(nan);
  q.mul(1e-45f);
  const double floor4 = 4.0 * std::log(double(est::LogProduct::kFactorMin));
  CHECK(std::fabs(double(q.log()) - floor4) <= bound(4, floor4));
  est::LogProduct c;
  c.mul(inf);
  c.mul(1e38f);
  const double cap2 = 2.0 * std::log(double(est::LogProduct::kFactorMax));
  CHECK(std::fabs(double(c.log()) - cap2) <= bound(2, cap2));
  // 360 factors at the floor: exponent -35 880, the hi part of e ln2 still exact.
  est::LogProduct f;
  for (int k = 0; k < 360; ++k) f.mul(0.0f);
  const double floor360 = 360.0 * std::log(double(est::LogProduct::kFactorMin));
  CHECK(std::isfinite(f.log()));
  CHECK(std::fabs(double(f.log()) - floor360) <= bound(360, floor360));
}

TEST_CASE("log product is bit-identical run to run and keeps the mantissa in [1, 2)", "[log_product]") {
  est::Rng a(9u), b(9u);
  est::LogProduct p, q;
  for (int k = 0; k < 1000; ++k) {
    p.mul(a.uniform(1e-6f, 50.0f));
    q.mul(b.uniform(1e-6f, 50.0f));
    REQUIRE(p.mantissa() >= 1.0f);
    REQUIRE(p.mantissa() < 2.0f);
  }
  const float lp = p.log(), lq = q.log();
  CHECK(std::memcmp(&lp, &lq, sizeof lp) == 0);
}
