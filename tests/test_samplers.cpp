// The samplers of est/random/samplers.hpp against their analytic distributions: moments within stated standard
// errors, Kolmogorov-Smirnov against the exact CDF, chi-square for the rejection sampler, densities that integrate
// to one, the give-up path, and bit-identical repeats. Seeds are fixed; the significance levels are stated per case.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "est/random/samplers.hpp"
#include "statistics.hpp"

namespace {

using est::Rng;
namespace stat = est::test;

// Sanitizer builds (no NDEBUG) run 5-10x slower and take a quarter of the draws; the tolerances follow n.
#ifdef NDEBUG
constexpr std::size_t kDraws = 400000;
#else
constexpr std::size_t kDraws = 100000;
#endif

constexpr double kSigma = 1.7;      // any sigma: the samplers scale linearly
constexpr double kMomentSE = 5.0;   // moment tolerances in standard errors (two-sided p ~ 6e-7 each)
constexpr double kAlpha = 0.001;    // KS and chi-square significance

template <typename Sampler>
std::vector<double> draw(Sampler sampler, std::uint64_t seed, std::size_t n) {
  Rng rng(seed);
  std::vector<double> x(n);
  for (double& v : x) v = static_cast<double>(sampler(rng));
  return x;
}

// Standardized even moments E[z^k], k = 4, 6, 8, of the sum of m uniforms on (-1, 1), exactly (by convolving raw
// moments, E[U^j] = 1/(j+1) for even j).
struct EvenMoments {
  double mu4, mu6, mu8;
};
EvenMoments sum_of_uniforms_moments(int m) {
  std::vector<double> raw(9, 0.0);  // raw moments of S_0 = 0
  raw[0] = 1.0;
  for (int i = 0; i < m; ++i) {
    std::vector<double> next(9, 0.0);
    for (int k = 0; k <= 8; ++k) {
      double binom = 1.0;
      for (int j = 0; j <= k; ++j) {
        const int u = k - j;
        if (u % 2 == 0) next[static_cast<std::size_t>(k)] += binom * raw[static_cast<std::size_t>(j)] / (u + 1.0);
        binom = binom * (k - j) / (j + 1.0);
      }
    }
    raw = next;
  }
  const double v = raw[2];
  return {raw[4] / (v * v), raw[6] / (v * v * v), raw[8] / (v * v * v * v)};
}

// Irwin-Hall CDF of the sum of n uniforms on [0, 1) (in double: the alternating sum loses ~1e-12 for n = 12).
double irwin_hall_cdf(double s, int n) {
  if (s <= 0.0) return 0.0;
  if (s >= n) return 1.0;
  double sum = 0.0, binom = 1.0, factorial = 1.0;
  for (int i = 2; i <= n; ++i) factorial *= i;
  for (int k = 0; k <= static_cast<int>(std::floor(s)); ++k) {
    sum += (k % 2 == 0 ? 1.0 : -1.0) * binom * std::pow(s - k, n);
    binom = binom * (n - k) / (k + 1.0);
  }
  return std::clamp(sum / factorial, 0.0, 1.0);
}

double triangular_cdf(double x, double sigma) {
  const double w = std::sqrt(6.0) * sigma;
  if (x <= -w) return 0.0;
  if (x >= w) return 1.0;
  return x < 0.0 ? (w + x) * (w + x) / (2.0 * w * w) : 1.0 - (w - x) * (w - x) / (2.0 * w * w);
}

void check_moments(const char* name, const std::vector<double>& x, double excess_kurtosis, const EvenMoments& em) {
  const stat::Moments m = stat::moments(x);
  const double var = kSigma * kSigma;
  const double se_mean = stat::mean_standard_error(var, x.size());
  const double se_var = stat::variance_standard_error(var, excess_kurtosis, x.size());
  const double se_kurt = stat::excess_kurtosis_standard_error(em.mu4, em.mu6, em.mu8, x.size());
  std::printf("samplers: %-12s n=%zu mean %+.5f (%.2f SE)  var %.5f (%+.2f SE)  excess kurtosis %+.4f vs %+.4f "
              "(%+.2f SE)  skewness %+.4f\n",
              name, x.size(), m.mean, m.mean / se_mean, m.variance, (m.variance - var) / se_var, m.excess_kurtosis,
              excess_kurtosis, (m.excess_kurtosis - excess_kurtosis) / se_kurt, m.skewness);
  CHECK(std::fabs(m.mean) <= kMomentSE * se_mean);
  CHECK(std::fabs(m.variance - var) <= kMomentSE * se_var);
  CHECK(std::fabs(m.excess_kurtosis - excess_kurtosis) <= kMomentSE * se_kurt);
  // Symmetric: the skewness SE is sqrt(6/n) for the normal and smaller for the lighter-tailed samplers.
  CHECK(std::fabs(m.skewness) <= kMomentSE * std::sqrt(6.0 / static_cast<double>(x.size())));
}

double normal_cdf_sigma(double x) { return stat::normal_cdf(x / kSigma); }

}  // namespace

TEST_CASE("Box-Muller: mean, variance and kurtosis of N(0, sigma^2) within 5 standard errors", "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_normal_box_muller(r, static_cast<float>(kSigma)); }, 11u, kDraws);
  check_moments("box_muller", x, 0.0, {3.0, 15.0, 105.0});
}

TEST_CASE("Box-Muller passes Kolmogorov-Smirnov against the normal CDF at alpha = 0.001", "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_normal_box_muller(r, static_cast<float>(kSigma)); }, 12u, kDraws);
  const double d = stat::ks_statistic(x, normal_cdf_sigma);
  const double crit = stat::ks_critical(x.size(), kAlpha);
  std::printf("samplers: box_muller KS D = %.5f, critical %.5f (alpha %.3f, n %zu)\n", d, crit, kAlpha, x.size());
  CHECK(d <= crit);
  // Power: the same draws against a 3 % wider normal are rejected, so the test can fail.
  const double d_wrong = stat::ks_statistic(x, [](double v) { return stat::normal_cdf(v / (1.03 * kSigma)); });
  CHECK(d_wrong > crit);
  // The tail bound of the header: |x| <= 5.77 sigma.
  for (double v : x) REQUIRE(std::fabs(v) <= 5.77 * kSigma);
}

TEST_CASE("sum of 12 uniforms: variance sigma^2 and excess kurtosis -0.1 within 5 standard errors", "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_normal_sum12(r, static_cast<float>(kSigma)); }, 21u, kDraws);
  check_moments("sum12", x, -0.1, sum_of_uniforms_moments(12));
  for (double v : x) REQUIRE(std::fabs(v) <= 6.0 * kSigma);
}

TEST_CASE("sum of 12 uniforms passes KS against the exact Irwin-Hall CDF, and is within 0.0024 of the normal CDF",
          "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_normal_sum12(r, static_cast<float>(kSigma)); }, 22u, kDraws);
  // x = sigma (S - 6) with S the sum of 12 uniforms on [0, 1).
  const double d = stat::ks_statistic(x, [](double v) { return irwin_hall_cdf(v / kSigma + 6.0, 12); });
  const double crit = stat::ks_critical(x.size(), kAlpha);
  // The largest distance between the Irwin-Hall(12) CDF, standardized, and the normal CDF, on a fine grid.
  double sup = 0.0;
  for (int i = -6000; i <= 6000; ++i) {
    const double z = i * 0.001;
    sup = std::max(sup, std::fabs(irwin_hall_cdf(z + 6.0, 12) - stat::normal_cdf(z)));
  }
  const double d_normal = stat::ks_statistic(x, normal_cdf_sigma);
  std::printf("samplers: sum12 KS D = %.5f vs Irwin-Hall, critical %.5f (alpha %.3f); D = %.5f vs normal, "
              "bound %.5f + %.5f\n",
              d, crit, kAlpha, d_normal, crit, sup);
  CHECK(d <= crit);
  CHECK(sup < 0.0024);  // sup |IH12 - Phi| = 0.00234
  CHECK(d_normal <= crit + sup);
}

TEST_CASE("triangular: variance sigma^2 and excess kurtosis -0.6 within 5 standard errors, support sqrt(6) sigma",
          "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_triangular(r, static_cast<float>(kSigma)); }, 31u, kDraws);
  check_moments("triangular", x, -0.6, sum_of_uniforms_moments(2));
  for (double v : x) REQUIRE(std::fabs(v) <= std::sqrt(6.0) * kSigma * (1.0 + 1e-6));
}

TEST_CASE("triangular passes KS against the triangular CDF at alpha = 0.001", "[samplers]") {
  const auto x = draw([](Rng& r) { return est::sample_triangular(r, static_cast<float>(kSigma)); }, 32u, kDraws);
  const double d = stat::ks_statistic(x, [](double v) { return triangular_cdf(v, kSigma); });
  const double crit = stat::ks_critical(x.size(), kAlpha);
  std::printf("samplers: triangular KS D = %.5f, critical %.5f (alpha %.3f, n %zu)\n", d, crit, kAlpha, x.size());
  CHECK(d <= crit);
  // Power: a normal of the same variance is rejected.
  CHECK(stat::ks_statistic(x, normal_cdf_sigma) > crit);
}

TEST_CASE("sample_normal is Box-Muller, bit for bit", "[samplers]") {
  Rng a(5u), b(5u);
  for (int i = 0; i < 1000; ++i) {
    const float u = est::sample_normal(a, 0.3f), v = est::sample_normal_box_muller(b, 0.3f);
    REQUIRE(std::memcmp(&u, &v, sizeof u) == 0);
  }
}

TEST_CASE("rejection sampler reproduces a Beta(3, 4) shape: chi-square over 20 cells at alpha = 0.001", "[samplers]") {
  // f(x) = x^2 (1 - x)^3 on [0, 1], unnormalized (integral 1/60), maximum f(2/5) = 0.03456.
  const auto f = [](float x) { return x * x * (1.0f - x) * (1.0f - x) * (1.0f - x); };
  const auto cdf = [](double x) {
    const double x3 = x * x * x;
    return 60.0 * (x3 / 3.0 - 3.0 * x3 * x / 4.0 + 3.0 * x3 * x * x / 5.0 - x3 * x3 / 6.0);
  };
  Rng rng(41u);
  constexpr int kCells = 20;
  std::vector<double> observed(kCells, 0.0), expected(kCells, 0.0);
  const std::size_t n = kDraws / 2;
  double tries = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const est::RejectionSample s = est::sample_rejection(rng, f, 0.0f, 1.0f, 0.035f, 1000u);
    REQUIRE(s.ok);
    REQUIRE(s.value >= 0.0f);
    REQUIRE(s.value < 1.0f);
    tries += s.tries;
    observed[static_cast<std::size_t>(std::min(kCells - 1, static_cast<int>(s.value * kCells)))] += 1.0;
  }
  for (int c = 0; c < kCells; ++c)
    expected[static_cast<std::size_t>(c)] =
        static_cast<double>(n) * (cdf((c + 1.0) / kCells) - cdf(c / double{kCells}));
  // Merge the sparse edge cells (expected < 5) into their neighbours.
  std::vector<double> obs, exp;
  double acc_o = 0.0, acc_e = 0.0;
  for (int c = 0; c < kCells; ++c) {
    acc_o += observed[static_cast<std::size_t>(c)];
    acc_e += expected[static_cast<std::size_t>(c)];
    if (acc_e >= 5.0) {
      obs.push_back(acc_o);
      exp.push_back(acc_e);
      acc_o = acc_e = 0.0;
    }
  }
  obs.back() += acc_o;
  exp.back() += acc_e;
  const double chi2 = stat::chi_square(obs, exp);
  const double dof = static_cast<double>(obs.size() - 1);
  const double crit = stat::chi_square_critical(dof, kAlpha);
  // The number of tries is geometric with p = (1/60) / 0.035: mean 1/p, variance (1 - p) / p^2.
  const double p = (1.0 / 60.0) / 0.035;
  const double mean_tries = tries / static_cast<double>(n);
  const double se_tries = std::sqrt((1.0 - p) / (p * p) / static_cast<double>(n));
  std::printf("samplers: rejection Beta(3,4) chi2 = %.2f, critical %.2f (%g dof, alpha %.3f); mean tries %.4f vs "
              "%.4f (%+.2f SE)\n",
              chi2, crit, dof, kAlpha, mean_tries, 1.0 / p, (mean_tries - 1.0 / p) / se_tries);
  CHECK(chi2 <= crit);
  CHECK(std::fabs(mean_tries - 1.0 / p) <= kMomentSE * se_tries);
}

TEST_CASE("rejection sampler reproduces a truncated Gaussian built from prob_normal: chi-square at alpha = 0.001",
          "[samplers]") {
  // N(0.5, 0.7^2) truncated to [-1, 2]: a skewed, non-trivial target, through the firmware's own density.
  const auto f = [](float x) { return est::prob_normal(x - 0.5f, 0.7f); };
  const double z_lo = stat::normal_cdf((-1.0 - 0.5) / 0.7), z_hi = stat::normal_cdf((2.0 - 0.5) / 0.7);
  const auto cdf = [&](double x) { return (stat::normal_cdf((x - 0.5) / 0.7) - z_lo) / (z_hi - z_lo); };
  Rng rng(42u);
  constexpr int kCells = 30;
  const std::size_t n = kDraws / 2;
  std::vector<double> observed(kCells, 0.0), expected(kCells, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const est::RejectionSample s = est::sample_rejection(rng, f, -1.0f, 2.0f, 0.58f, 1000u);  // peak 0.5699
    REQUIRE(s.ok);
    const int c = std::clamp(static_cast<int>((s.value + 1.0f) / 3.0f * kCells), 0, kCells - 1);
    observed[static_cast<std::size_t>(c)] += 1.0;
  }
  for (int c = 0; c < kCells; ++c)
    expected[static_cast<std::size_t>(c)] =
        static_cast<double>(n) * (cdf(-1.0 + 3.0 * (c + 1.0) / kCells) - cdf(-1.0 + 3.0 * c / double{kCells}));
  for (double e : expected) REQUIRE(e >= 5.0);
  const double chi2 = stat::chi_square(observed, expected);
  const double crit = stat::chi_square_critical(kCells - 1.0, kAlpha);
  std::printf("samplers: rejection truncated normal chi2 = %.2f, critical %.2f (%d dof, alpha %.3f)\n", chi2, crit,
              kCells - 1, kAlpha);
  CHECK(chi2 <= crit);
  // Power: the untruncated-mean-shifted target (mean 0.55) is rejected by the same statistic.
  std::vector<double> shifted(kCells, 0.0);
  const double s_lo = stat::normal_cdf((-1.0 - 0.55) / 0.7), s_hi = stat::normal_cdf((2.0 - 0.55) / 0.7);
  for (int c = 0; c < kCells; ++c) {
    const auto g = [&](double x) { return (stat::normal_cdf((x - 0.55) / 0.7) - s_lo) / (s_hi - s_lo); };
    shifted[static_cast<std::size_t>(c)] =
        static_cast<double>(n) * (g(-1.0 + 3.0 * (c + 1.0) / kCells) - g(-1.0 + 3.0 * c / double{kCells}));
  }
  CHECK(stat::chi_square(observed, shifted) > crit);
}

TEST_CASE("rejection sampler gives up after exactly max_tries tries, two draws each", "[samplers]") {
  const auto zero = [](float) { return 0.0f; };
  for (std::uint32_t max_tries : {1u, 7u, 100u}) {
    Rng rng(99u), reference(99u);
    const est::RejectionSample s = est::sample_rejection(rng, zero, -1.0f, 1.0f, 1.0f, max_tries);
    CHECK_FALSE(s.ok);
    CHECK(s.tries == max_tries);
    for (std::uint32_t i = 0; i < 2u * max_tries; ++i) reference();
    CHECK(rng == reference);
  }
  // max_tries = 0: no try, no draw.
  Rng rng(99u);
  const est::RejectionSample s = est::sample_rejection(rng, zero, -1.0f, 1.0f, 1.0f, 0u);
  CHECK_FALSE(s.ok);
  CHECK(s.tries == 0u);
  CHECK(rng == Rng(99u));
  // A density that is positive everywhere under f_max accepts on the first try when the height draw is below it.
  Rng one(3u);
  const est::RejectionSample t = est::sample_rejection(one, [](float) { return 2.0f; }, 0.0f, 1.0f, 1.0f, 5u);
  CHECK(t.ok);
  CHECK(t.tries == 1u);
}

TEST_CASE("prob_normal integrates to 1 within 1e-5 and matches the analytic density within 1e-5 relative",
          "[samplers]") {
  for (float sigma_f : {0.01f, 0.5f, 1.0f, 3.0f, 250.0f}) {
    const double sigma = sigma_f;
    // Simpson's rule on [-12 sigma, 12 sigma], 24000 intervals: the rule's own error is far below 1e-9.
    const int n = 24000;
    const double a = -12.0 * sigma, h = 24.0 * sigma / n;
    double sum = 0.0, worst_rel = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double x = a + h * i;
      const double p = est::prob_normal(static_cast<float>(x), sigma_f);
      const double xf = static_cast<float>(x);
      const double exact =
          std::exp(-0.5 * (xf / sigma) * (xf / sigma)) / (std::sqrt(2.0 * 3.14159265358979323846) * sigma);
      if (std::fabs(xf) < 8.0 * sigma) worst_rel = std::max(worst_rel, std::fabs(p / exact - 1.0));
      sum += (i == 0 || i == n ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0)) * p;
    }
    const double integral = sum * h / 3.0;
    INFO("sigma = " << sigma << ": integral " << integral << ", worst relative error " << worst_rel);
    CHECK(std::fabs(integral - 1.0) <= 1e-5);
    // Within |a| <= 8 sigma: z^2/2 <= 32 is known to ~4e-6 absolute in float, so exp adds that relatively.
    CHECK(worst_rel <= 1e-5);
  }
  CHECK(est::prob_normal(0.0f, 1.0f) == Approx(0.3989422804).epsilon(1e-7));
  CHECK(est::prob_normal(20.0f, 1.0f) == 0.0f);  // underflows beyond ~14.4 sigma, never NaN
}

TEST_CASE("prob_triangular integrates to 1 within 1e-6 and has the hand-computed shape", "[samplers]") {
  for (float sigma_f : {0.01f, 1.0f, 7.5f}) {
    const double sigma = sigma_f;
    // The density is piecewise linear with kinks at -w, 0, w: the trapezoid rule on a grid through them is exact
    // up to float rounding of the values.
    const double w = std::sqrt(6.0) * sigma;
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double x = -1.5 * w + 3.0 * w * i / n;
      sum += (i == 0 || i == n ? 0.5 : 1.0) * static_cast<double>(est::prob_triangular(static_cast<float>(x), sigma_f));
    }
    INFO("sigma = " << sigma);
    CHECK(std::fabs(sum * 3.0 * w / n - 1.0) <= 1e-6 + 3.0 / n);
    CHECK(est::prob_triangular(0.0f, sigma_f) == Approx(1.0 / w).epsilon(1e-6));
    CHECK(est::prob_triangular(static_cast<float>(w / 2.0), sigma_f) == Approx(0.5 / w).epsilon(1e-5));
    CHECK(est::prob_triangular(static_cast<float>(w * 1.001), sigma_f) == 0.0f);
    CHECK(est::prob_triangular(static_cast<float>(-w * 1.001), sigma_f) == 0.0f);
  }
}

TEST_CASE("same seed gives the same bits, and each sampler takes a fixed number of draws", "[samplers]") {
  const auto same = [](auto sampler, std::uint32_t draws_per_call) {
    Rng a(777u), b(777u), c(778u), counted(777u);
    bool any_differs = false;
    for (int i = 0; i < 2000; ++i) {
      const float u = sampler(a), v = sampler(b), w = sampler(c);
      REQUIRE(std::memcmp(&u, &v, sizeof u) == 0);
      any_differs = any_differs || std::memcmp(&u, &w, sizeof u) != 0;
      for (std::uint32_t k = 0; k < draws_per_call; ++k) counted();
      REQUIRE(a == counted);
    }
    CHECK(any_differs);
  };
  same([](Rng& r) { return est::sample_normal_box_muller(r, 0.2f); }, 2u);
  same([](Rng& r) { return est::sample_normal_sum12(r, 0.2f); }, 12u);
  same([](Rng& r) { return est::sample_triangular(r, 0.2f); }, 2u);
}
