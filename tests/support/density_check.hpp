#pragma once
// Checks that a motion model's sampler and its density agree: the density is integrated over the cells of a 3-D
// grid by product Gauss-Legendre cubature (in double), and the sampler's histogram on the same cells is compared
// with it by Pearson's chi-square and by total-variation distance. Header-only, for the motion model tests.
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "statistics.hpp"

namespace est::test {

// A box split into cells[0] x cells[1] x cells[2] cells (the chi-square cells). Coordinates are whatever the test
// chooses (x, y, theta; or rho, psi, theta with the polar factor rho put into the integrand).
struct Grid3 {
  double lo[3];
  double hi[3];
  int cells[3];

  int count() const { return cells[0] * cells[1] * cells[2]; }
  // Cell of point p, or -1 outside the box.
  int index(const std::array<double, 3>& p) const {
    int idx[3];
    for (int k = 0; k < 3; ++k) {
      const double t = (p[static_cast<std::size_t>(k)] - lo[k]) / (hi[k] - lo[k]);
      if (!(t >= 0.0 && t < 1.0)) return -1;
      idx[k] = static_cast<int>(t * cells[k]);
      if (idx[k] >= cells[k]) idx[k] = cells[k] - 1;
    }
    return (idx[2] * cells[1] + idx[1]) * cells[0] + idx[0];
  }
};

// Integral of f over every cell of g: each cell is split into sub^3 sub-cells with 3x3x3 Gauss-Legendre points
// (exact for polynomials of degree 5 per axis), so count() * sub^3 * 27 evaluations.
inline std::vector<double> integrate_cells(const Grid3& g, int sub,
                                           const std::function<double(double, double, double)>& f) {
  static const double kNode[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
  static const double kWeight[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  std::vector<double> mass(static_cast<std::size_t>(g.count()), 0.0);
  double h[3];
  for (int k = 0; k < 3; ++k) h[k] = (g.hi[k] - g.lo[k]) / (g.cells[k] * sub);
  const double vol = h[0] * h[1] * h[2] / 8.0;
  for (int c2 = 0; c2 < g.cells[2] * sub; ++c2)
    for (int c1 = 0; c1 < g.cells[1] * sub; ++c1)
      for (int c0 = 0; c0 < g.cells[0] * sub; ++c0) {
        double s = 0.0;
        for (int i2 = 0; i2 < 3; ++i2)
          for (int i1 = 0; i1 < 3; ++i1)
            for (int i0 = 0; i0 < 3; ++i0) {
              const double a = g.lo[0] + h[0] * (c0 + 0.5 + 0.5 * kNode[i0]);
              const double b = g.lo[1] + h[1] * (c1 + 0.5 + 0.5 * kNode[i1]);
              const double c = g.lo[2] + h[2] * (c2 + 0.5 + 0.5 * kNode[i2]);
              s += kWeight[i0] * kWeight[i1] * kWeight[i2] * f(a, b, c);
            }
        const int cell = ((c2 / sub) * g.cells[1] + c1 / sub) * g.cells[0] + c0 / sub;
        mass[static_cast<std::size_t>(cell)] += s * vol;
      }
  return mass;
}

inline double total(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

struct FitResult {
  double chi2 = 0.0;
  double critical = 0.0;       // chi-square critical value at the requested significance
  int dof = 0;
  double total_variation = 0.0;  // 0.5 sum |observed/n - expected/n| over the cells used
  std::size_t outside = 0;       // samples outside the box
};

// Pearson's chi-square of the samples' histogram against n * cell_mass. Cells expecting fewer than 5 samples are
// pooled with everything outside the box into one cell whose expectation is n (1 - sum of the kept masses), i.e.
// the density is taken to integrate to one (checked separately).
inline FitResult goodness_of_fit(const Grid3& g, const std::vector<double>& cell_mass,
                                 const std::vector<std::array<double, 3>>& samples, double alpha) {
  FitResult r;
  const double n = static_cast<double>(samples.size());
  std::vector<double> observed(cell_mass.size(), 0.0);
  for (const auto& s : samples) {
    const int i = g.index(s);
    if (i < 0) {
      ++r.outside;
    } else {
      observed[static_cast<std::size_t>(i)] += 1.0;
    }
  }
  std::vector<double> obs, expd;
  double kept_mass = 0.0, kept_obs = 0.0;
  for (std::size_t i = 0; i < cell_mass.size(); ++i) {
    if (n * cell_mass[i] >= 5.0) {
      obs.push_back(observed[i]);
      expd.push_back(n * cell_mass[i]);
      kept_mass += cell_mass[i];
      kept_obs += observed[i];
    }
  }
  const double pooled_expected = n * (1.0 - kept_mass);
  if (pooled_expected >= 5.0) {
    obs.push_back(n - kept_obs);
    expd.push_back(pooled_expected);
  }
  r.chi2 = chi_square(obs, expd);
  r.dof = static_cast<int>(obs.size()) - 1;
  r.critical = chi_square_critical(r.dof, alpha);
  double tv = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) tv += (obs[i] > expd[i] ? obs[i] - expd[i] : expd[i] - obs[i]);
  r.total_variation = 0.5 * tv / n;
  return r;
}

}  // namespace est::test
