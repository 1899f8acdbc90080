#include <catch2/catch.hpp>
#include <cmath>

#include "est/filter/kld_sampling.hpp"
#include "est/random/xoshiro128.hpp"
#include "statistics.hpp"

TEST_CASE("KLD sample count matches the chi-square quantile it approximates", "[kld]") {
  // n = chi2_{k-1, 1-delta} / (2 eps); the Wilson-Hilferty form is within 1 % for k >= 3 (Fox 2003, eq. 11).
  for (std::uint32_t k : {3u, 10u, 50u, 200u, 1000u}) {
    const double exact = est::test::chi_square_critical(k - 1.0, 0.01) / (2.0 * 0.05);
    CHECK(est::kld_sample_count(k, 0.05f, 2.326348f) == Approx(exact).epsilon(1e-4));
  }
  // Fox's table: k = 2 bins, eps = 0.05, delta = 0.01 needs chi2_{1,0.99}/0.1 ~ 66 particles (Wilson-Hilferty
  // overestimates at one degree of freedom; 1.1 relative tolerance stated).
  CHECK(est::kld_sample_count(2u, 0.05f, 2.326348f) == Approx(6.635 / 0.1).epsilon(0.1));
  CHECK(est::kld_sample_count(1u, 0.05f, 2.326f) == 1.0f);
}

TEST_CASE("bin counter counts distinct bins and saturates instead of overflowing", "[kld]") {
  est::BinCounter<64> bins;
  bins.clear();
  for (int rep = 0; rep < 3; ++rep)
    for (int i = 0; i < 20; ++i) bins.insert(i, -i, i % 3);
  CHECK(bins.count() == 20u);
  CHECK_FALSE(bins.saturated());
  bins.clear();
  CHECK(bins.count() == 0u);
  for (int i = 0; i < 40; ++i) bins.insert(i, 0, 0);
  CHECK(bins.saturated());
}

TEST_CASE("a concentrated cloud asks for fewer particles than a spread one", "[kld]") {
  static est::ParticleSet<4000> s;
  static est::BinCounter<4096> bins;
  est::Rng rng(8u);
  est::KldConfig cfg;
  s.set_count(4000);
  auto v = s.view();
  for (std::uint32_t i = 0; i < v.count; ++i) {
    v.x[i] = rng.uniform(-0.2f, 0.2f);
    v.y[i] = rng.uniform(-0.2f, 0.2f);
    v.theta[i] = rng.uniform(-0.05f, 0.05f);
    v.log_w[i] = 0.0f;
  }
  const auto tight = est::kld_particle_count(s.view(), cfg, 4000u, bins);
  for (std::uint32_t i = 0; i < v.count; ++i) {
    v.x[i] = rng.uniform(-10.0f, 10.0f);
    v.y[i] = rng.uniform(-10.0f, 10.0f);
    v.theta[i] = rng.uniform(-3.1f, 3.1f);
  }
  const auto spread = est::kld_particle_count(s.view(), cfg, 4000u, bins);
  // The tight cloud covers exactly 2 x 2 x 2 = 8 bins: n(8) = 70 (1 - 2/63 + sqrt(2/63) z)^3 ~ 185 particles.
  CHECK(tight == static_cast<std::uint32_t>(std::ceil(est::kld_sample_count(8u, cfg.epsilon, cfg.z_one_minus_delta))));
  CHECK(tight > cfg.n_min);
  CHECK(tight < 200u);
  CHECK(spread == 4000u);
}
