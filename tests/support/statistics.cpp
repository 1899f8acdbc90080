#include "statistics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace est::test {

Moments moments(const std::vector<double>& x) {
  Moments m;
  const double n = static_cast<double>(x.size());
  if (x.size() < 4) return m;
  double sum = 0.0;
  for (double v : x) sum += v;
  m.mean = sum / n;
  double m2 = 0.0, m3 = 0.0, m4 = 0.0;
  for (double v : x) {
    const double d = v - m.mean;
    m2 += d * d;
    m3 += d * d * d;
    m4 += d * d * d * d;
  }
  m.variance = m2 / (n - 1.0);
  const double pop_var = m2 / n;
  m.skewness = (m3 / n) / std::pow(pop_var, 1.5);
  m.excess_kurtosis = (m4 / n) / (pop_var * pop_var) - 3.0;
  return m;
}

double mean_standard_error(double variance, std::size_t n) { return std::sqrt(variance / static_cast<double>(n)); }

double variance_standard_error(double variance, double excess_kurtosis, std::size_t n) {
  // Var(s^2) ~ sigma^4 (2/(n-1) + kappa/n)
  const double nn = static_cast<double>(n);
  return variance * std::sqrt(2.0 / (nn - 1.0) + excess_kurtosis / nn);
}

double excess_kurtosis_standard_error(double mu4, double mu6, double mu8, std::size_t n) {
  // g = m4 / m2^2 with Var(m2) = mu4 - 1, Var(m4) = mu8 - mu4^2, Cov(m2, m4) = mu6 - mu4 (per draw, sigma = 1).
  const double v = (mu8 - mu4 * mu4) + 4.0 * mu4 * mu4 * (mu4 - 1.0) - 4.0 * mu4 * (mu6 - mu4);
  return std::sqrt(v / static_cast<double>(n));
}

double ks_statistic(std::vector<double> x, const std::function<double(double)>& cdf) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n});
  }
  return d;
}

double ks_critical(std::size_t n, double alpha) {
  double c = 0.0;
  if (alpha == 0.05) c = 1.3581;
  else if (alpha == 0.01) c = 1.6276;
  else if (alpha == 0.001) c = 1.9495;
  else throw std::invalid_argument("ks_critical: alpha must be 0.05, 0.01 or 0.001");
  return c / std::sqrt(static_cast<double>(n));
}

double chi_square(const std::vector<double>& observed, const std::vector<double>& expected) {
  if (observed.size() != expected.size()) throw std::invalid_argument("chi_square: sizes differ");
  double s = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const double d = observed[i] - expected[i];
    s += d * d / expected[i];
  }
  return s;
}

double chi_square_critical(double k, double alpha) {
  const double z = normal_quantile(1.0 - alpha);
  const double a = 2.0 / (9.0 * k);
  const double t = 1.0 - a + z * std::sqrt(a);
  return k * t * t * t;
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("normal_quantile: p outside (0, 1)");
  // Bisection on the CDF: slow but exact to double precision, and only called a few times.
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normal_cdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace est::test
