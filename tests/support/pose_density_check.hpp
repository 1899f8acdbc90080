#pragma once
// Sample histogram against a density over (x, y, theta): the density is integrated over each cell of a box grid
// by adaptive 3-point Gauss-Legendre, and compared with the counts by Pearson's chi-square (cells expected
// below 5 merged, plus one cell for everything outside the box) and by total variation. Header-only, host, double.
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "statistics.hpp"

namespace est::test {

struct PoseBox {
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  std::array<int, 3> cells;  // histogram cells per axis
  double tol = 1e-7;         // absolute quadrature tolerance per cell (probability)
  int max_depth = 4;         // levels of adaptive refinement per cell
};

struct PoseDensityComparison {
  double mass_in_box = 0.0;     // integral of the density over the box
  double chi2 = 0.0;
  double dof = 0.0;
  double critical = 0.0;        // chi-square critical value at the requested significance
  double total_variation = 0.0; // 0.5 sum |observed/N - expected/N| over the merged cells
  std::size_t merged_cells = 0;
};

// Integral of f(x, y, theta) over the box [lo, hi] by Gauss-Legendre 3 x 3 x 3 on sub^3 sub-cells.
template <typename Density>
double integrate_box(const Density& f, const std::array<double, 3>& lo, const std::array<double, 3>& hi, int sub) {
  static const double kNode[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
  static const double kWeight[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double h[3] = {(hi[0] - lo[0]) / sub, (hi[1] - lo[1]) / sub, (hi[2] - lo[2]) / sub};
  double total = 0.0;
  for (int i = 0; i < sub; ++i)
    for (int j = 0; j < sub; ++j)
      for (int k = 0; k < sub; ++k) {
        const double c[3] = {lo[0] + (i + 0.5) * h[0], lo[1] + (j + 0.5) * h[1], lo[2] + (k + 0.5) * h[2]};
        double s = 0.0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            for (int e = 0; e < 3; ++e)
              s += kWeight[a] * kWeight[b] * kWeight[e] *
                   f(c[0] + 0.5 * h[0] * kNode[a], c[1] + 0.5 * h[1] * kNode[b], c[2] + 0.5 * h[2] * kNode[e]);
        total += s;
      }
  return total * 0.125 * h[0] * h[1] * h[2];
}

// Adaptive: the box's Gauss-Legendre value is compared with that of its 8 halves, and halves are refined (up to
// max_depth levels, each with an eighth of the tolerance) until the two agree within tol. Needed where the density
// has an edge (a steering stop) or a steep ridge that a fixed rule integrates badly.
template <typename Density>
double integrate_adaptive(const Density& f, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                          double tol, int max_depth, double coarse) {
  const double fine = integrate_box(f, lo, hi, 2);
  if (max_depth <= 0 || std::fabs(fine - coarse) <= tol) return fine;
  double total = 0.0;
  for (int c = 0; c < 8; ++c) {
    std::array<double, 3> l2{}, h2{};
    for (std::size_t d = 0; d < 3; ++d) {
      const double mid = 0.5 * (lo[d] + hi[d]);
      const bool upper = ((c >> d) & 1) != 0;
      l2[d] = upper ? mid : lo[d];
      h2[d] = upper ? hi[d] : mid;
    }
    total += integrate_adaptive(f, l2, h2, tol / 8.0, max_depth - 1, integrate_box(f, l2, h2, 1));
  }
  return total;
}

template <typename Density>
double integrate_adaptive(const Density& f, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                          double tol, int max_depth) {
  return integrate_adaptive(f, lo, hi, tol, max_depth, integrate_box(f, lo, hi, 1));
}

// The integral of f over [lo, hi] split into n x n x n cells, each refined by integrate_adaptive to `tol`: the
// quadrature error is below n^3 tol.
template <typename Density>
double integrate_grid(const Density& f, const std::array<double, 3>& lo, const std::array<double, 3>& hi, int n,
                      double tol, int max_depth) {
  double mass = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int idx[3] = {i, j, k};
        std::array<double, 3> c_lo{}, c_hi{};
        for (std::size_t d = 0; d < 3; ++d) {
          const double w = (hi[d] - lo[d]) / n;
          c_lo[d] = lo[d] + w * idx[d];
          c_hi[d] = c_lo[d] + w;
        }
        mass += integrate_adaptive(f, c_lo, c_hi, tol, max_depth);
      }
  return mass;
}

template <typename Density>
PoseDensityComparison compare_pose_density(const std::vector<std::array<double, 3>>& samples, const Density& f,
                                           const PoseBox& box, double alpha) {
  const int nx = box.cells[0], ny = box.cells[1], nt = box.cells[2];
  const std::size_t ncell = static_cast<std::size_t>(nx * ny * nt);
  std::vector<double> observed(ncell + 1, 0.0);  // last: outside the box
  const double w[3] = {(box.hi[0] - box.lo[0]) / nx, (box.hi[1] - box.lo[1]) / ny, (box.hi[2] - box.lo[2]) / nt};
  for (const auto& s : samples) {
    int idx[3];
    bool inside = true;
    for (int d = 0; d < 3; ++d) {
      const double q = std::floor((s[static_cast<std::size_t>(d)] - box.lo[static_cast<std::size_t>(d)]) / w[d]);
      idx[d] = static_cast<int>(q);
      if (!(q >= 0.0 && q < box.cells[static_cast<std::size_t>(d)])) inside = false;
    }
    if (inside)
      observed[static_cast<std::size_t>((idx[0] * ny + idx[1]) * nt + idx[2])] += 1.0;
    else
      observed[ncell] += 1.0;
  }
  const double n = static_cast<double>(samples.size());
  std::vector<double> expected(ncell + 1, 0.0);
  PoseDensityComparison out;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nt; ++k) {
        const std::array<double, 3> lo = {box.lo[0] + i * w[0], box.lo[1] + j * w[1], box.lo[2] + k * w[2]};
        const std::array<double, 3> hi = {lo[0] + w[0], lo[1] + w[1], lo[2] + w[2]};
        const double p = integrate_adaptive(f, lo, hi, box.tol, box.max_depth);
        expected[static_cast<std::size_t>((i * ny + j) * nt + k)] = n * p;
        out.mass_in_box += p;
      }
  expected[ncell] = n * (1.0 - out.mass_in_box);
  // Merge every cell expected below 5 into one.
  std::vector<double> obs_m, exp_m;
  double obs_small = 0.0, exp_small = 0.0;
  for (std::size_t c = 0; c <= ncell; ++c) {
    if (expected[c] >= 5.0) {
      obs_m.push_back(observed[c]);
      exp_m.push_back(expected[c]);
    } else {
      obs_small += observed[c];
      exp_small += expected[c];
      ++out.merged_cells;
    }
  }
  if (exp_small > 0.0) {
    obs_m.push_back(obs_small);
    exp_m.push_back(exp_small > 5.0 ? exp_small : 5.0);  // never divide by a tiny expectation
  }
  out.chi2 = chi_square(obs_m, exp_m);
  out.dof = static_cast<double>(obs_m.size()) - 1.0;
  out.critical = chi_square_critical(out.dof, alpha);
  double tv = 0.0;
  for (std::size_t c = 0; c < obs_m.size(); ++c) tv += std::fabs(obs_m[c] - exp_m[c]);
  out.total_variation = 0.5 * tv / n;
  return out;
}

// A box over +-4 sample standard deviations of each coordinate of pose samples, split into `cells`.
inline PoseBox box_around(const std::vector<std::array<double, 3>>& s, std::array<int, 3> cells) {
  PoseBox b{};
  for (std::size_t d = 0; d < 3; ++d) {
    std::vector<double> v;
    for (const auto& q : s) v.push_back(q[d]);
    const auto m = moments(v);
    b.lo[d] = m.mean - 4.0 * std::sqrt(m.variance);
    b.hi[d] = m.mean + 4.0 * std::sqrt(m.variance);
  }
  b.cells = cells;
  b.tol = 2e-6;  // per cell: 0.2 counts of 100000, against a sampling sd of >= 2.2 counts in any unmerged cell
  b.max_depth = 3;
  return b;
}

}  // namespace est::test
