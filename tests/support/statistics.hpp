#pragma once
// Goodness-of-fit tools for the tests: moments, Kolmogorov-Smirnov, chi-square, all in double on the host.
#include <cstddef>
#include <functional>
#include <vector>

namespace est::test {

struct Moments {
  double mean = 0.0;
  double variance = 0.0;  // unbiased
  double skewness = 0.0;
  double excess_kurtosis = 0.0;
};
Moments moments(const std::vector<double>& x);

// Standard error of the sample mean and of the sample variance for n draws of a distribution with the given
// variance and excess kurtosis (for tolerances stated in sigmas).
double mean_standard_error(double variance, std::size_t n);
double variance_standard_error(double variance, double excess_kurtosis, std::size_t n);
// Standard error of the sample excess kurtosis for n draws of a symmetric distribution with standardized moments
// E[z^4], E[z^6], E[z^8] (delta method; sqrt(24 / n) for the normal: 3, 15, 105).
double excess_kurtosis_standard_error(double mu4, double mu6, double mu8, std::size_t n);

// D_n = sup |F_n(x) - F(x)|; sorts a copy.
double ks_statistic(std::vector<double> x, const std::function<double(double)>& cdf);
// Asymptotic critical value of D_n at significance alpha (Kolmogorov distribution; alpha in {0.05, 0.01, 0.001}).
double ks_critical(std::size_t n, double alpha);

// Pearson's statistic over cells with expected counts (cells with expected < 5 should be merged by the caller).
double chi_square(const std::vector<double>& observed, const std::vector<double>& expected);
// Upper quantile of chi-square with k degrees of freedom at significance alpha, by the Wilson-Hilferty
// approximation (relative error below 1 % for k >= 3).
double chi_square_critical(double k, double alpha);

// Standard normal CDF and quantile.
double normal_cdf(double z);
double normal_quantile(double p);

}  // namespace est::test
