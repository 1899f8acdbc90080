#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "caster_agreement.hpp"
#include "datasets.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

est::OccupancyGridStorage<1024, 1024> g_grid;
est::DistanceTransformStorage<1024, 1024> g_edt;
// Office 400 x 300 at 64 headings (15 MiB), or the Intel map 888 x 848 at 32 headings (46 MiB).
est::HeadingRangeTableStorage<888, 848, 32> g_table;

struct ErrorStats {
  int rays = 0;
  double mean = 0.0, median = 0.0, p90 = 0.0, max = 0.0, within_10cm = 0.0;
};

// |table - exact| over random rays from random free cells in random directions.
ErrorStats table_error(const est::OccupancyGrid& g, const est::HeadingRangeTable& t, int rays, float max_range,
                       std::uint64_t seed) {
  const est::GridRayCaster exact(g);
  std::vector<double> err;
  for (const test_support::TestRay& r : test_support::random_free_rays(g, rays, seed))
    err.push_back(std::fabs(double(t.cast(r.x, r.y, r.dx, r.dy, max_range)) -
                            double(exact.cast(r.x, r.y, r.dx, r.dy, max_range))));
  ErrorStats s;
  s.rays = rays;
  for (double e : err) {
    s.mean += e / rays;
    s.within_10cm += e <= 0.10 ? 1.0 / rays : 0.0;
  }
  std::sort(err.begin(), err.end());
  s.median = err[err.size() / 2];
  s.p90 = err[err.size() * 9 / 10];
  s.max = err.back();
  return s;
}

void print(const char* name, const ErrorStats& s, double build_ms) {
  std::printf("heading range table on %s: build %.0f ms; %d rays: mean |table - exact| %.3f m, median %.3f m, "
              "p90 %.3f m, max %.2f m, %.1f %% within 0.10 m\n",
              name, build_ms, s.rays, s.mean, s.median, s.p90, s.max, 100.0 * s.within_10cm);
}

// Built with the distance-transform caster: the exact traversal's ranges (test_ray_casting) in less time.
double build(int bins, float max_range) {
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(g_table.build(g_grid.grid(), est::DistanceTransformRayCaster(g_grid.grid(), g_edt.view()), bins,
                        max_range) == est::HeadingRangeTableStatus::ok);
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("heading table keeps the exact caster's conventions", "[heading_range_table]") {
  // 40 x 20 cells of 0.1 m, a wall column at cx = 30; open to the left and up.
  REQUIRE(g_grid.configure(40, 20, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(30, 0, 30, 19, est::kOccupiedCell);
  build(16, 10.0f);
  const est::HeadingRangeTable t = g_table.view();
  REQUIRE(t.valid());
  // Along a table heading from a cell centre the entry is the exact range, to 1/32 cell: 3.0 - 0.55 m.
  CHECK(t.cast(0.55f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.45f).margin(0.1f / 32.0f));
  // Off the centre along the beam, the offset is subtracted: still exact for a wall across the beam.
  CHECK(t.cast(0.52f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.48f).margin(0.1f / 32.0f));
  CHECK(t.cast(3.05f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start in an occupied cell
  CHECK(t.cast(-0.1f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start off the map
  CHECK(t.cast(NAN, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);       // non-finite start
  CHECK(t.cast(0.55f, 1.05f, NAN, 0.0f, 10.0f) == 0.0f);      // non-finite direction
  CHECK(t.cast(0.55f, 1.05f, -1.0f, 0.0f, 10.0f) == 10.0f);   // leaves the map: no hit
  CHECK(t.cast(0.55f, 1.05f, 1.0f, 0.0f, 1.0f) == 1.0f);      // capped at the query's max range
  CHECK(t.cast(0.55f, 1.05f, -1.0f, 0.0f, 50.0f) == 10.0f);   // ... and at the table's build range
  CHECK(t.cast(0.55f, 1.05f, 1.0f, 0.0f, 0.0f) == 0.0f);      // max range <= 0
}

TEST_CASE("heading table rejects bad build inputs with a reason", "[heading_range_table]") {
  est::sim::make_office_map(g_grid);
  const est::GridRayCaster exact(g_grid.grid());
  REQUIRE(g_table.build(g_grid.grid(), exact, 4, 1.0f) == est::HeadingRangeTableStatus::ok);
  CHECK(g_table.build(g_grid.grid(), exact, 48, 20.0f) == est::HeadingRangeTableStatus::bad_bins);
  CHECK(g_table.build(g_grid.grid(), exact, 2, 20.0f) == est::HeadingRangeTableStatus::bad_bins);
  CHECK(g_table.build(g_grid.grid(), exact, 1024, 20.0f) == est::HeadingRangeTableStatus::too_large);
  CHECK(g_table.build(g_grid.grid(), exact, 16, 0.0f) == est::HeadingRangeTableStatus::bad_range);
  CHECK(g_table.build(g_grid.grid(), exact, 16, NAN) == est::HeadingRangeTableStatus::bad_range);
  CHECK(g_table.build(g_grid.grid(), exact, 16, 300.0f) == est::HeadingRangeTableStatus::bad_range);  // > 4095 cells
  CHECK(g_table.build(est::OccupancyGrid{}, exact, 16, 20.0f) == est::HeadingRangeTableStatus::bad_grid);
  CHECK(g_table.view().bins() == 4);  // a rejected build leaves the previous table as it was
}

// Stated bounds (measured: see the header): the bulk of rays is within a few cm; rays passing near a corner see the
// other side of it, so the max is not bounded below the range and the mean carries that tail.
TEST_CASE("heading table agrees with the exact caster within its stated error on the synthetic office",
          "[heading_range_table]") {
  est::sim::make_office_map(g_grid);
  const double ms = build(64, 20.0f);
  const ErrorStats s = table_error(g_grid.grid(), g_table.view(), 20000, 20.0f, 5u);
  print("the synthetic office (400 x 300 at 0.05 m, 64 headings, 20 m)", s, ms);
  CHECK(s.median <= 0.02);
  CHECK(s.within_10cm >= 0.85);
  CHECK(s.mean <= 0.20);
}

TEST_CASE("heading table agrees with the exact caster within its stated error on the Intel map",
          "[heading_range_table][dataset]") {
  const std::string dir = test_support::dataset_or_skip("carmen-radish-logs") + "/..";
  est::sim::load_trinary_pgm_map(dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm", g_grid);
  REQUIRE(g_grid.width() == 888);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  // The distance-transform caster gives the exact ranges (test_ray_casting) in less time.
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(g_table.build(g_grid.grid(), est::DistanceTransformRayCaster(g_grid.grid(), g_edt.view()), 32, 20.0f) ==
          est::HeadingRangeTableStatus::ok);
  const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ErrorStats s = table_error(g_grid.grid(), g_table.view(), 20000, 20.0f, 13u);
  print("the Intel map (888 x 848 at 0.05 m, 32 headings, 20 m)", s, ms);
  CHECK(s.median <= 0.05);
  CHECK(s.within_10cm >= 0.60);
  CHECK(s.mean <= 0.90);
}

TEST_CASE("beam model on the heading table is close to the exact one and bit-identical run to run",
          "[heading_range_table]") {
  est::sim::make_office_map(g_grid);
  build(64, 20.0f);
  const est::HeadingRangeTable table = g_table.view();
  const est::GridRayCaster exact(g_grid.grid());
  const est::BeamRangeFinderModel model = test_support::beam_model(20.0f);
  REQUIRE(model.ready());
  // A 360-beam scan cast exactly from a free pose; particles around it.
  const est::Pose2 truth{5.5f, 7.3f, 0.3f};
  static est::PreparedScan<360> scan;
  REQUIRE(test_support::prepare_exact_scan(g_grid.grid(), truth, 20.0f, scan));
  static est::BeamBearingsStorage<360> bearings;
  REQUIRE(bearings.prepare(scan.beams(), table));
  est::Rng rng(21u);
  int close = 0;
  for (int i = 0; i < 200; ++i) {
    const est::Pose2 x{truth.x + rng.uniform(-0.3f, 0.3f), truth.y + rng.uniform(-0.3f, 0.3f),
                       truth.theta + rng.uniform(-0.1f, 0.1f)};
    const float l_exact = est::beam_range_finder_model(scan.beams(), x, {}, exact, model);
    const float l_table = est::beam_range_finder_model(scan.beams(), bearings.view(), x, {}, table, model);
    const float l_again = est::beam_range_finder_model(scan.beams(), bearings.view(), x, {}, table, model);
    REQUIRE(std::memcmp(&l_table, &l_again, sizeof(float)) == 0);
    REQUIRE(std::isfinite(l_table));
    // Per beam within 0.5 nats on average (the log density moves ~(z - z*) / sigma^2 per metre of z*).
    if (std::fabs(l_table - l_exact) <= 0.5f * 360.0f) ++close;
  }
  std::printf("beam model, table vs exact: %d of 200 particles within 0.5 nats per beam on average\n", close);
  CHECK(close >= 190);
  // The likelihood still peaks at the truth: the true pose beats a pose 0.3 m off.
  const float at_truth = est::beam_range_finder_model(scan.beams(), bearings.view(), truth, {}, table, model);
  const float off = est::beam_range_finder_model(scan.beams(), bearings.view(), {truth.x + 0.3f, truth.y, truth.theta},
                                                 {}, table, model);
  CHECK(at_truth > off);
  // Bearings prepared for another table size are refused (every beam floored).
  static est::BeamBearingsStorage<60> wrong;
  CHECK_FALSE(wrong.prepare(scan.beams(), table));
  CHECK(est::beam_range_finder_model(scan.beams(), wrong.view(), truth, {}, table, model) ==
        360.0f * est::kBeamLogDensityFloor);
}
