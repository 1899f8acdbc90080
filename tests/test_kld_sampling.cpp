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

namespace {

// Table 8.4's loop with samples from `sample(rng, x, y, theta)`: the number drawn when the rule first says enough.
template <typename Sample>
std::uint32_t samples_until_done(const est::KldConfig& cfg, std::uint32_t n_max, const Sample& sample, est::Rng& rng) {
  static est::KldStoppingRule<4096> rule;
  rule.start(cfg, n_max);
  std::uint32_t n = 0;
  for (; !rule.done(n); ++n) {
    float x = 0.0f, y = 0.0f, theta = 0.0f;
    sample(rng, x, y, theta);
    rule.add(x, y, theta);
  }
  return n;
}

}  // namespace

TEST_CASE("the stopping rule asks for n_chi(k) of the bins the samples drawn occupy, and at least n_min", "[kld]") {
  est::KldConfig cfg;
  cfg.n_min = 50;
  est::Rng rng(8u);
  // Samples in exactly 2 x 2 x 2 = 8 bins: n(8) = 70 (1 - 2/63 + sqrt(2/63) z)^3 ~ 185 draws.
  const auto tight = [](est::Rng& r, float& x, float& y, float& theta) {
    x = r.uniform(-0.2f, 0.2f);
    y = r.uniform(-0.2f, 0.2f);
    theta = r.uniform(-0.05f, 0.05f);
  };
  const std::uint32_t n = samples_until_done(cfg, 4000u, tight, rng);
  CHECK(n == static_cast<std::uint32_t>(std::ceil(est::kld_sample_count(8u, cfg.epsilon, cfg.z_one_minus_delta))));
  CHECK(n > cfg.n_min);
  // One bin only: n_chi(1) = 1, so n_min decides.
  const auto one_bin = [](est::Rng& r, float& x, float& y, float& theta) {
    x = r.uniform(0.1f, 0.2f);
    y = 0.3f;
    theta = 0.01f;
  };
  CHECK(samples_until_done(cfg, 4000u, one_bin, rng) == cfg.n_min);
}

TEST_CASE("a concentrated cloud asks for fewer particles than a spread one", "[kld]") {
  est::KldConfig cfg;
  est::Rng rng(9u);
  const auto around = [](float s_xy, float s_theta) {
    return [=](est::Rng& r, float& x, float& y, float& theta) {
      x = r.uniform(-s_xy, s_xy);
      y = r.uniform(-s_xy, s_xy);
      theta = r.uniform(-s_theta, s_theta);
    };
  };
  const std::uint32_t tight = samples_until_done(cfg, 4000u, around(0.4f, 0.15f), rng);
  const std::uint32_t spread = samples_until_done(cfg, 4000u, around(10.0f, 3.1f), rng);
  INFO("tight " << tight << ", spread " << spread);
  CHECK(tight > cfg.n_min);
  CHECK(tight < 400u);
  CHECK(spread == 4000u);  // every draw a new bin: n_chi(k) ~ 10 k outruns the draws up to n_max
}

TEST_CASE("draws of which a tenth open new bins never satisfy the rule before n_max", "[kld]") {
  // n_chi(k) ~ (k - 1) / (2 eps) = 10 (k - 1) at eps = 0.05: once more than one draw in ten opens a bin (augmented
  // MCL injecting >10 % random poses), the required count grows faster than the draws and the set goes to n_max.
  est::KldConfig cfg;
  est::Rng rng(10u);
  std::uint32_t i = 0;
  const auto mixed = [&i](est::Rng& r, float& x, float& y, float& theta) {
    const bool fresh = (i++ % 8u) == 0u;
    x = fresh ? 0.5f * static_cast<float>(i) : r.uniform(0.0f, 0.4f);
    y = fresh ? 7.0f : 0.2f;
    theta = 0.0f;
  };
  CHECK(samples_until_done(cfg, 3000u, mixed, rng) == 3000u);
  // The same draws with a new bin one time in 20 stop well before.
  i = 0;
  const auto rare = [&i](est::Rng& r, float& x, float& y, float& theta) {
    const bool fresh = (i++ % 20u) == 0u;
    x = fresh ? 0.5f * static_cast<float>(i) : r.uniform(0.0f, 0.4f);
    y = fresh ? 7.0f : 0.2f;
    theta = 0.0f;
  };
  CHECK(samples_until_done(cfg, 3000u, rare, rng) < 1500u);
}
