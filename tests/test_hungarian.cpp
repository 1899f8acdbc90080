#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "est/assoc/hungarian.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

// Brute force: the minimum over every injective map of rows into (columns or "unassigned" at cost gate).
double brute_force(const est::CostMatrix<5, 6>& m, int rows, int cols, float gate) {
  double best = 1e300;
  std::vector<int> choice(static_cast<std::size_t>(rows), -1);
  // Enumerate choices in {-1, 0..cols-1}^rows.
  const int base = cols + 1;
  int total = 1;
  for (int r = 0; r < rows; ++r) total *= base;
  for (int code = 0; code < total; ++code) {
    int c = code;
    bool ok = true;
    std::vector<bool> used(static_cast<std::size_t>(cols), false);
    double cost = 0.0;
    for (int r = 0; r < rows && ok; ++r) {
      const int col = c % base - 1;
      c /= base;
      if (col < 0) {
        cost += static_cast<double>(gate);
      } else if (used[static_cast<std::size_t>(col)] || m.cost[r][col] > gate) {
        ok = false;
      } else {
        used[static_cast<std::size_t>(col)] = true;
        cost += static_cast<double>(m.cost[r][col]);
      }
    }
    if (ok) best = std::min(best, cost);
  }
  return best;
}

}  // namespace

TEST_CASE("gated assignment equals brute force on random cost matrices", "[hungarian]") {
  est::Rng rng(31u);
  for (int t = 0; t < 300; ++t) {
    const int rows = 1 + static_cast<int>(rng.below(5u));
    const int cols = 1 + static_cast<int>(rng.below(6u));
    const float gate = rng.uniform(1.0f, 12.0f);
    est::CostMatrix<5, 6> m;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) m.cost[r][c] = rng.uniform(0.0f, 15.0f);
    const auto a = est::gated_assignment(m, rows, cols, gate);
    REQUIRE(a.ok);
    CHECK(static_cast<double>(a.total_cost) == Approx(brute_force(m, rows, cols, gate)).epsilon(1e-5));
    // A consistent, gated, one-to-one result.
    int assigned = 0;
    for (int r = 0; r < rows; ++r) {
      const int c = a.col_of_row[r];
      if (c < 0) continue;
      ++assigned;
      CHECK(a.row_of_col[c] == r);
      CHECK(m.cost[r][c] <= gate);
    }
    CHECK(assigned == a.assigned);
  }
}

TEST_CASE("8 robots seen anonymously: the Mahalanobis assignment recovers who is who, an outlier stays unassigned",
          "[hungarian]") {
  est::Rng rng(32u);
  float px[8], py[8];
  for (int i = 0; i < 8; ++i) {
    px[i] = static_cast<float>(i % 4) * 2.0f;
    py[i] = static_cast<float>(i / 4) * 2.0f;
  }
  int perm[8] = {3, 7, 0, 5, 1, 6, 2, 4};  // measurement k sees robot perm[k]
  const float var = 0.1f * 0.1f;
  est::CostMatrix<9, 8> m;
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 8; ++i) {
      const float zx = px[perm[k]] + rng.uniform(-0.1f, 0.1f), zy = py[perm[k]] + rng.uniform(-0.1f, 0.1f);
      m.cost[k][i] = ((zx - px[i]) * (zx - px[i]) + (zy - py[i]) * (zy - py[i])) / var;
    }
  for (int i = 0; i < 8; ++i) m.cost[8][i] = 100.0f + static_cast<float>(i);  // far from every robot
  const auto a = est::gated_assignment(m, 9, 8, 13.8f);
  REQUIRE(a.ok);
  for (int k = 0; k < 8; ++k) CHECK(a.col_of_row[k] == perm[k]);
  CHECK(a.col_of_row[8] == -1);
  CHECK(a.assigned == 8);
}

TEST_CASE("bad sizes and NaN costs are refused", "[hungarian]") {
  est::CostMatrix<2, 2> m;
  CHECK_FALSE(est::gated_assignment(m, 3, 2, 1.0f).ok);
  CHECK_FALSE(est::gated_assignment(m, 2, 2, 0.0f).ok);
  m.cost[1][1] = std::nanf("");
  CHECK_FALSE(est::gated_assignment(m, 2, 2, 1.0f).ok);
}
