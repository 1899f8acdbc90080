#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "est/map/distance_transform.hpp"
#include "est/random/xoshiro128.hpp"

namespace {
est::OccupancyGridStorage<64, 64> g_grid;
est::DistanceTransformStorage<64, 64> g_edt;

// Brute force: squared distance in cells from every cell centre to the nearest occupied centre, -1 if none.
long brute_d2(const est::OccupancyGrid& g, std::int32_t x, std::int32_t y) {
  long best = -1;
  for (std::int32_t j = 0; j < g.height(); ++j)
    for (std::int32_t i = 0; i < g.width(); ++i)
      if (g.is_occupied(i, j)) {
        const long d2 = long(i - x) * (i - x) + long(j - y) * (j - y);
        if (best < 0 || d2 < best) best = d2;
      }
  return best;
}
}  // namespace

TEST_CASE("the distance transform equals brute force on random small grids, exactly", "[distance_transform]") {
  est::Rng rng(99u);
  const std::int32_t sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {7, 5}, {16, 16}, {33, 20}, {64, 64}, {50, 3}};
  const float densities[] = {0.0f, 0.01f, 0.1f, 0.5f, 0.95f};
  int grids = 0;
  for (const auto& s : sizes)
    for (float density : densities) {
      REQUIRE(g_grid.configure(s[0], s[1], 0.05f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
      for (std::int32_t y = 0; y < s[1]; ++y)
        for (std::int32_t x = 0; x < s[0]; ++x) {
          const float u = rng.uniform();
          g_grid.set(x, y, u < density ? est::kOccupiedCell : (u < 0.9f ? est::kFreeCell : est::kUnknownCell));
        }
      const est::OccupancyGrid g = g_grid.grid();
      REQUIRE(g_edt.build(g) == est::MapStatus::ok);
      const est::DistanceTransform dt = g_edt.view();
      ++grids;
      for (std::int32_t y = 0; y < s[1]; ++y)
        for (std::int32_t x = 0; x < s[0]; ++x) {
          const long d2 = brute_d2(g, x, y);
          INFO("grid " << s[0] << "x" << s[1] << " density " << density << " cell " << x << "," << y);
          if (d2 < 0) {
            REQUIRE(dt.units(x, y) == est::kDistanceSaturated);
          } else {
            // floor(16 sqrt(d2)), computed exactly in long double for these small integers.
            const auto expect = static_cast<std::uint16_t>(std::floor(16.0L * std::sqrt(static_cast<long double>(d2))));
            REQUIRE(dt.units(x, y) == expect);
            REQUIRE((dt.units(x, y) == 0) == g.is_occupied(x, y));
          }
        }
    }
  CHECK(grids == 40);
}

TEST_CASE("distance transform values in metres are floored to 1/16 cell", "[distance_transform]") {
  REQUIRE(g_grid.configure(20, 10, 0.05f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.set(0, 0, est::kOccupiedCell);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const est::DistanceTransform dt = g_edt.view();
  CHECK(dt.units(3, 4) == 80);                                      // 5 cells exactly
  CHECK(dt.metres(3, 4) == Approx(0.25f).epsilon(1e-6));
  CHECK(dt.units(1, 1) == 22);                                      // 16 sqrt(2) = 22.63
  const float d = dt.metres(19, 9);
  const float truth = 0.05f * std::sqrt(19.0f * 19.0f + 81.0f);
  CHECK(d <= truth);
  CHECK(truth - d < 0.05f / 16.0f);
}

TEST_CASE("a grid larger than the transform's capacity is refused", "[distance_transform]") {
  static est::OccupancyGridStorage<80, 10> wide;
  REQUIRE(wide.configure(80, 10, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  CHECK(g_edt.build(wide.grid()) == est::MapStatus::too_large);
  CHECK(g_edt.build(est::OccupancyGrid{}) == est::MapStatus::empty);
}
