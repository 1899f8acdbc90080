#include "maps/learn_intrinsic_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace est::sim {
namespace {

double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double p_hit(double z, double zs, double sigma, double zm) {
  const double mass = std::max(phi((zm - zs) / sigma) - phi(-zs / sigma), 1e-300);
  const double u = (z - zs) / sigma;
  return std::exp(-0.5 * u * u) / (sigma * std::sqrt(2.0 * M_PI)) / mass;
}

double p_short(double z, double zs, double lambda) {
  if (z > zs || lambda * zs < 1e-12) return 0.0;
  return lambda * std::exp(-lambda * z) / -std::expm1(-lambda * zs);
}

}  // namespace

LearnResult learn_intrinsic_parameters(const std::vector<RangeSample>& data, const BeamModelParams& initial,
                                       int max_iterations, double tolerance) {
  if (data.empty()) throw std::invalid_argument("learn_intrinsic_parameters: no data");
  for (const auto& s : data)
    if (!std::isfinite(s.z) || !std::isfinite(s.z_star) || s.z < 0.0 || s.z_star < 0.0)
      throw std::invalid_argument("learn_intrinsic_parameters: non-finite or negative range");
  const double zm = initial.range_max;
  double w_hit = initial.z_hit, w_short = initial.z_short, w_max = initial.z_max, w_rand = initial.z_rand;
  double sigma = initial.sigma_hit, lambda = initial.lambda_short;
  const std::size_t n = data.size();
  std::vector<double> e_hit(n), e_short(n);
  LearnResult out;
  for (int it = 1; it <= max_iterations; ++it) {
    // E step
    double s_hit = 0.0, s_short = 0.0, s_max = 0.0, s_rand = 0.0, ll = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double z = data[i].z, zs = std::min(data[i].z_star, zm);
      if (z >= zm) {
        e_hit[i] = e_short[i] = 0.0;
        s_max += 1.0;
        ll += std::log(std::max(w_max, 1e-300));
        continue;
      }
      const double a = w_hit * p_hit(z, zs, sigma, zm), b = w_short * p_short(z, zs, lambda), c = w_rand / zm;
      const double total = std::max(a + b + c, 1e-300);
      e_hit[i] = a / total;
      e_short[i] = b / total;
      s_hit += e_hit[i];
      s_short += e_short[i];
      s_rand += c / total;
      ll += std::log(total);
    }
    // M step
    const double nd = static_cast<double>(n);
    const double nw_hit = s_hit / nd, nw_short = s_short / nd, nw_max = s_max / nd, nw_rand = s_rand / nd;
    double num = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = data[i].z - std::min(data[i].z_star, zm);
      num += e_hit[i] * d * d;
    }
    const double nsigma = s_hit > 0.0 ? std::sqrt(num / s_hit) : sigma;
    double nlambda = lambda;
    if (s_short > 0.0) {
      // d/dlambda of sum e_i [log lambda - lambda z_i - log(1 - e^{-lambda z*_i})] is decreasing in lambda.
      auto grad = [&](double l) {
        double g = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
          if (e_short[i] == 0.0) continue;
          const double zs = std::min(data[i].z_star, zm);
          g += e_short[i] * (1.0 / l - data[i].z - zs / std::expm1(l * zs));
        }
        return g;
      };
      double lo = 1e-4, hi = 1e3;
      for (int k = 0; k < 40; ++k) {  // the bracket shrinks to a ratio of 1 + 1e-11
        const double mid = std::sqrt(lo * hi);
        (grad(mid) > 0.0 ? lo : hi) = mid;
      }
      nlambda = std::sqrt(lo * hi);
    }
    const double change = std::max({std::fabs(nw_hit - w_hit), std::fabs(nw_short - w_short),
                                    std::fabs(nw_max - w_max), std::fabs(nw_rand - w_rand),
                                    std::fabs(nsigma - sigma) / sigma, std::fabs(nlambda - lambda) / lambda});
    w_hit = nw_hit;
    w_short = nw_short;
    w_max = nw_max;
    w_rand = nw_rand;
    sigma = nsigma;
    lambda = nlambda;
    out.iterations = it;
    out.log_likelihood = ll;
    if (change < tolerance) {
      out.converged = true;
      break;
    }
  }
  out.params = initial;
  out.params.z_hit = static_cast<float>(w_hit);
  out.params.z_short = static_cast<float>(w_short);
  out.params.z_max = static_cast<float>(w_max);
  out.params.z_rand = static_cast<float>(w_rand);
  out.params.sigma_hit = static_cast<float>(sigma);
  out.params.lambda_short = static_cast<float>(lambda);
  return out;
}

}  // namespace est::sim
