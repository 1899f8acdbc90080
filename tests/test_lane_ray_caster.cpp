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
#include "est/map/lane_ray_caster.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_lanes.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

est::OccupancyGridStorage<1024, 1024> g_grid;
// Enough for the Intel map (888 x 848) at 64 headings (bench_sensor_models prints the figures).
est::LaneRayCasterStorage<256, 200000, 12000000, 12000000> g_lanes;

using test_support::Agreement;

void print(const char* name, const Agreement& s, double build_ms, const est::LaneRayCasterBuffer& b) {
  std::printf("lane ray caster on %s: build %.0f ms, %u entries, %u lanes, %.1f MiB; %d rays: %d identical to the "
              "exact traversal (%.3f %%), %.3f %% within one cell, worst |error| %.3f m\n",
              name, build_ms, b.entries(), b.lanes(), b.bytes_used() / 1048576.0, s.rays, s.identical,
              100.0 * s.identical / s.rays, 100.0 * s.within_cell / s.rays, s.worst);
}

double build(int bins) {
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(g_lanes.build(g_grid.grid(), bins) == est::LaneRayCasterStatus::ok);
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("lane caster keeps the exact caster's conventions", "[lane_ray_caster]") {
  // 40 x 20 cells of 0.1 m, a wall column at cx = 30; open to the left and up.
  REQUIRE(g_grid.configure(40, 20, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(30, 0, 30, 19, est::kOccupiedCell);
  build(16);
  const est::LaneRayCaster c = g_lanes.view();
  REQUIRE(c.valid());
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.45f).margin(1e-5f));
  CHECK(c.cast(0.52f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.48f).margin(1e-5f));
  CHECK(c.cast(3.05f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start in an occupied cell
  CHECK(c.cast(-0.1f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start off the map
  CHECK(c.cast(NAN, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);       // non-finite start
  CHECK(c.cast(0.55f, 1.05f, NAN, 0.0f, 10.0f) == 0.0f);      // non-finite direction
  CHECK(c.cast(0.55f, 1.05f, -1.0f, 0.0f, 10.0f) == 10.0f);   // leaves the map: no hit
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 1.0f) == 1.0f);      // capped at max range
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 0.0f) == 0.0f);      // max range <= 0
  CHECK(c.cast(0.55f, 1.05f, 0.0f, 1.0f, 10.0f) == 10.0f);    // along the wall, never reaching it
  // A heading given far from the ray's is replaced by the ray's own: still exact.
  CHECK(c.cast_bins(0.55f, 1.05f, 1.0f, 0.0f, 5.0f, 10.0f) == Approx(2.45f).margin(1e-5f));
}

TEST_CASE("lane caster rejects bad builds with a reason", "[lane_ray_caster]") {
  est::sim::make_office_map(g_grid);
  CHECK(g_lanes.build(g_grid.grid(), 48) == est::LaneRayCasterStatus::bad_bins);
  CHECK(g_lanes.build(g_grid.grid(), 2) == est::LaneRayCasterStatus::bad_bins);
  CHECK(g_lanes.build(g_grid.grid(), 512) == est::LaneRayCasterStatus::bad_bins);  // above the storage's T
  CHECK(!g_lanes.view().valid());
  CHECK(g_lanes.build(est::OccupancyGrid{}, 16) == est::LaneRayCasterStatus::bad_grid);
  static est::LaneRayCasterStorage<16, 100000, 1000, 1000000> small;  // room for the lanes, not the entries
  CHECK(small.build(g_grid.grid(), 16) == est::LaneRayCasterStatus::too_many_entries);
  static est::LaneRayCasterStorage<16, 100, 1000000, 1000000> narrow;
  CHECK(narrow.build(g_grid.grid(), 16) == est::LaneRayCasterStatus::too_many_lanes);
  CHECK(!narrow.view().valid());
}

// The accuracy claim: >= 99.9 % of rays within one cell of the exact traversal (measured: every ray identical).
TEST_CASE("lane caster agrees with the exact traversal on the synthetic office", "[lane_ray_caster]") {
  est::sim::make_office_map(g_grid);
  for (int bins : {16, 64, 256}) {
    const double ms = build(bins);
    for (float range : {2.0f, 20.0f}) {
      const Agreement s =
          test_support::random_rays(g_grid.grid(), g_lanes.view(), 20000, range, 7u + static_cast<unsigned>(bins));
      char name[96];
      std::snprintf(name, sizeof name, "the synthetic office (400 x 300 at 0.05 m), %d headings, %.0f m", bins,
                    static_cast<double>(range));
      print(name, s, ms, g_lanes);
      CHECK(s.within_cell >= s.rays * 999 / 1000);
      CHECK(s.identical >= s.rays * 999 / 1000);
      CHECK(s.worst <= 20.0);
    }
  }
}

TEST_CASE("lane caster agrees with the exact traversal at cell centres and along the axes", "[lane_ray_caster]") {
  // Rays through cell corners (45 deg from centres) and along grid lines, where the traversal breaks ties.
  est::sim::make_office_map(g_grid);
  build(64);
  const Agreement s = test_support::centre_rays(g_grid.grid(), g_lanes.view(), 20.0f);
  std::printf("lane ray caster, %d rays from cell centres at multiples of 45 deg: %d identical, worst %.3f m\n",
              s.rays, s.identical, s.worst);
  CHECK(s.identical >= s.rays * 999 / 1000);
  CHECK(s.worst <= 0.05 + 1e-6);
}

TEST_CASE("lane caster agrees with the exact traversal on the Intel map", "[lane_ray_caster][dataset]") {
  const std::string dir = test_support::dataset_or_skip("carmen-radish-logs") + "/..";
  est::sim::load_trinary_pgm_map(dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm", g_grid);
  REQUIRE(g_grid.width() == 888);
  for (int bins : {64, 128}) {
    const double ms = build(bins);
    for (float range : {5.0f, 30.0f}) {
      const Agreement s =
          test_support::random_rays(g_grid.grid(), g_lanes.view(), 20000, range, 13u + static_cast<unsigned>(bins));
      char name[96];
      std::snprintf(name, sizeof name, "the Intel map (888 x 848 at 0.05 m), %d headings, %.0f m", bins,
                    static_cast<double>(range));
      print(name, s, ms, g_lanes);
      CHECK(s.within_cell >= s.rays * 999 / 1000);
      CHECK(s.identical >= s.rays * 999 / 1000);
    }
  }
}

TEST_CASE("beam model on the lane caster gives the exact caster's densities, their product in log space",
          "[lane_ray_caster]") {
  est::sim::make_office_map(g_grid);
  build(64);
  const est::LaneRayCaster lanes = g_lanes.view();
  const est::GridRayCaster exact(g_grid.grid());
  est::BeamModelParams bp;
  bp.range_max = 20.0f;
  est::BeamRangeFinderModel model;
  REQUIRE(model.configure(bp) == est::SensorModelStatus::ok);
  const est::Pose2 truth{5.5f, 7.3f, 0.3f};
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 360.0f, 360, 0.05f, 20.0f};
  std::vector<float> ranges(360);
  for (int k = 0; k < 360; ++k) {
    const float a = truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    ranges[static_cast<std::size_t>(k)] = exact.cast(truth.x, truth.y, std::cos(a), std::sin(a), 20.0f);
  }
  static est::PreparedScan<360> scan;
  REQUIRE(scan.prepare(layout, ranges.data(), 1) == est::ScanStatus::ok);
  const est::ScanBeams z = scan.beams();
  static est::BeamBearingsStorage<360> bearings;
  REQUIRE(bearings.prepare(z, lanes.bins()));
  static est::BeamReadingsStorage<360> readings;
  REQUIRE(readings.prepare(z, model));
  est::Rng rng(21u);
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const est::Pose2 x{truth.x + rng.uniform(-0.3f, 0.3f), truth.y + rng.uniform(-0.3f, 0.3f),
                       truth.theta + rng.uniform(-0.1f, 0.1f)};
    // The exact caster's per-beam log densities, summed in double: the reference of LogProduct's bound.
    const est::SensorFrame f = est::sensor_frame(x, {});
    double ref = 0.0;
    for (std::int32_t k = 0; k < z.count; ++k) {
      const float dx = f.c * z.ux[k] - f.s * z.uy[k], dy = f.s * z.ux[k] + f.c * z.uy[k];
      const float e = exact.cast(f.x, f.y, dx, dy, 20.0f);
      const float l = lanes.cast(f.x, f.y, dx, dy, 20.0f);
      REQUIRE(std::memcmp(&e, &l, sizeof(float)) == 0);  // the same z* on every beam
      ref += static_cast<double>(model.log_density(z.is_max[k] ? 20.0f : z.range[k], e));
    }
    const float fast = est::beam_range_finder_model(z, bearings.view(), readings.view(), x, {}, lanes, model);
    const float again = est::beam_range_finder_model(z, bearings.view(), readings.view(), x, {}, lanes, model);
    REQUIRE(std::memcmp(&fast, &again, sizeof(float)) == 0);
    const double bound = z.count * std::ldexp(1.0, -24) + 4.0 * std::fabs(ref) * std::ldexp(1.0, -23);
    CHECK(std::fabs(double(fast) - ref) <= bound);
    worst = std::max(worst, std::fabs(double(fast) - ref));
  }
  std::printf("beam model on the lane caster: worst |log q - sum of exact log densities| %.2e nats over 200 "
              "particles, 360 beams\n", worst);
  // Bearings prepared for another heading count, or readings for another scan, are refused.
  static est::BeamBearingsStorage<360> wrong;
  REQUIRE(wrong.prepare(z, 32));
  CHECK(est::beam_range_finder_model(z, wrong.view(), readings.view(), truth, {}, lanes, model) ==
        360.0f * est::kBeamLogDensityFloor);
  CHECK(est::beam_range_finder_model(z, bearings.view(), readings.view(), truth, {}, est::LaneRayCaster{}, model) ==
        360.0f * est::kBeamLogDensityFloor);
}
