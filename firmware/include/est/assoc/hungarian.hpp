#pragma once
// Gated maximum-likelihood assignment of anonymous measurements to robots (or features) by the Hungarian algorithm
// (Kuhn-Munkres with potentials, O(rows^2 cols)): the assignment minimizing the sum of Mahalanobis costs
// d^2 = nu^T S^-1 nu, where a measurement may also stay unassigned at cost `gate` (a dummy column per row), so a
// pairing beyond the gate is never made and an outlier does not steal a robot. This is the joint maximum-likelihood
// assignment when every pairing has the same log det S; for more robots than PermutationBelief can enumerate.
// Bounded: at most Rows outer steps of at most (Cols + Rows + 1) augmenting iterations of (Cols + Rows) work each.
#include <cstdint>

#include "est/math/fmath.hpp"

namespace est {

// cost[r][c]: the cost (e.g. Mahalanobis d^2) of giving row r (a measurement) to column c (a robot).
template <int Rows, int Cols>
struct CostMatrix {
  float cost[static_cast<unsigned>(Rows)][static_cast<unsigned>(Cols)] = {};
};

template <int Rows, int Cols>
struct AssignmentResult {
  std::int32_t col_of_row[static_cast<unsigned>(Rows)];  // the column assigned to each row, -1 if left unassigned
  std::int32_t row_of_col[static_cast<unsigned>(Cols)];  // the inverse, -1 if no row took the column
  float total_cost = 0.0f;                               // sum of assigned costs plus gate per unassigned row
  std::int32_t assigned = 0;
  bool ok = false;                                       // false for bad sizes or non-finite costs
};

// Minimum-cost assignment of `rows` rows to `cols` columns (rows <= Rows, cols <= Cols), cost[r][c] >= 0, with
// unassignment at cost gate > 0. Costs above the gate (or +inf) are treated as forbidden.
template <int Rows, int Cols>
AssignmentResult<Rows, Cols> gated_assignment(const CostMatrix<Rows, Cols>& m, int rows, int cols, float gate) {
  AssignmentResult<Rows, Cols> out;
  for (int r = 0; r < Rows; ++r) out.col_of_row[r] = -1;
  for (int c = 0; c < Cols; ++c) out.row_of_col[c] = -1;
  if (rows < 0 || rows > Rows || cols < 0 || cols > Cols || !(gate > 0.0f) || !fmath::isfinite(gate)) return out;
  constexpr int kW = Cols + Rows;  // real columns, then one dummy (stay unassigned) per row
  const float forbidden = 2.0f * gate + 1.0f;  // dearer than any dummy: never part of an optimum
  const int w = cols + rows;
  auto a = [&](int r, int c) -> float {  // 0-based
    if (c >= cols) return gate;
    const float x = m.cost[r][c];
    if (x != x || x < 0.0f) return -1.0f;  // flagged below
    return x > gate ? forbidden : x;
  };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (a(r, c) < 0.0f) return out;

  // Potentials u (rows), v (columns) and the matching p[col] = row, 1-based with column 0 as the free root.
  float u[static_cast<unsigned>(Rows + 1)] = {};
  float v[static_cast<unsigned>(kW + 1)] = {};
  std::int32_t p[static_cast<unsigned>(kW + 1)] = {};
  std::int32_t way[static_cast<unsigned>(kW + 1)] = {};
  float minv[static_cast<unsigned>(kW + 1)];
  bool used[static_cast<unsigned>(kW + 1)];
  constexpr float kInf = 3.0e38f;
  for (int i = 1; i <= rows; ++i) {
    p[0] = i;
    int j0 = 0;
    for (int j = 0; j <= w; ++j) {
      minv[j] = kInf;
      used[j] = false;
    }
    for (int iter = 0; iter <= w; ++iter) {  // each pass marks one more column used: at most w + 1 passes
      used[j0] = true;
      const int i0 = p[j0];
      float delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= w; ++j) {
        if (used[j]) continue;
        const float cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= w; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
      if (p[j0] == 0) break;
    }
    for (int iter = 0; iter <= w && j0 != 0; ++iter) {  // unwind the augmenting path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    }
  }
  out.total_cost = 0.0f;
  for (int j = 1; j <= w; ++j) {
    const int r = p[j] - 1;
    if (r < 0) continue;
    const int c = j - 1;
    const float x = a(r, c);
    if (c < cols && x <= gate) {
      out.col_of_row[r] = c;
      out.row_of_col[c] = r;
      out.total_cost += x;
      ++out.assigned;
    } else {
      out.total_cost += gate;
    }
  }
  out.ok = true;
  return out;
}

}  // namespace est
