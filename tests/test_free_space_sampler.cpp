#include <catch2/catch.hpp>
#include <cmath>

#include "est/filter/free_space_sampler.hpp"
#include "statistics.hpp"

namespace {

est::OccupancyGridStorage<100, 60> g_grid;
est::DistanceTransformStorage<100, 60> g_edt;

// 10 m x 6 m at 0.1 m: walls around, a 2 m x 2 m block at x in [2, 4), y in [2, 4), an unknown strip y in [5, 5.9).
void room() {
  REQUIRE(g_grid.configure(100, 60, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(0, 0, 99, 0, est::kOccupiedCell);
  g_grid.fill_rect(0, 59, 99, 59, est::kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 59, est::kOccupiedCell);
  g_grid.fill_rect(99, 0, 99, 59, est::kOccupiedCell);
  g_grid.fill_rect(20, 20, 39, 39, est::kOccupiedCell);
  g_grid.fill_rect(1, 50, 98, 58, est::kUnknownCell);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
}

}  // namespace

TEST_CASE("free-space draws land only on free cells clear of walls, uniformly", "[free_space_sampler]") {
  room();
  const est::FreeSpaceSampler draw(g_grid.grid(), g_edt.view(), 0.3f);
  REQUIRE(draw.valid());
  est::Rng rng(9u);
  const int n = 20000;
  int left = 0, failed = 0;
  std::vector<double> headings;
  for (int i = 0; i < n; ++i) {
    est::Pose2 p;
    if (!draw(rng, p)) {
      ++failed;
      continue;
    }
    std::int32_t cx = 0, cy = 0;
    REQUIRE(g_grid.grid().world_to_cell(p.x, p.y, cx, cy));
    REQUIRE(g_grid.grid().classify(cx, cy) == est::CellClass::free);
    REQUIRE(g_edt.view().metres(cx, cy) >= 0.3f);
    left += p.x < 5.0f ? 1 : 0;
    headings.push_back(static_cast<double>(p.theta));
  }
  CHECK(failed == 0);  // ~60 % admissible: 0.4^24 per draw
  // Admissible cells (centre at least 3 cells from every occupied centre, free, not unknown): columns 3..96, rows
  // 3..49, minus the block grown by 3 cells (Euclidean corners). Counted by hand (a double loop in Python): 1633
  // left of x = 5 m, 2209 right, so the expected share is 0.4250; 4 sigma of a binomial over 20000 draws = 0.014.
  CHECK(static_cast<double>(left) / n == Approx(0.4250).margin(0.014));
  CHECK(est::test::ks_statistic(headings, [](double t) { return (t + M_PI) / (2.0 * M_PI); }) <
        est::test::ks_critical(headings.size(), 0.001));
}

TEST_CASE("a map with no admissible cell makes every draw fail after its bounded tries", "[free_space_sampler]") {
  REQUIRE(g_grid.configure(10, 10, 0.1f, 0.0f, 0.0f, est::kOccupiedCell) == est::MapStatus::ok);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const est::FreeSpaceSampler draw(g_grid.grid(), g_edt.view(), 0.0f, 5u);
  est::Rng rng(1u);
  est::Pose2 p{1.0f, 2.0f, 3.0f};
  CHECK_FALSE(draw(rng, p));
  CHECK(p.x == 1.0f);
  CHECK_FALSE(est::FreeSpaceSampler{}(rng, p));  // no map
}
