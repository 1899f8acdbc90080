#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "est/map/distance_transform.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"

namespace {

// 8 m x 6 m at 0.05 m: walls, a partition, two boxes; 32 headings per cell (1.2 MiB).
est::OccupancyGridStorage<160, 120> g_grid;
est::DistanceTransformStorage<160, 120> g_edt;
est::HeadingRangeTableStorage<160, 120, 32> g_table;
est::PreparedScan<360> g_scan;
est::BeamBearingsStorage<360> g_bearings;
est::BeamReadingsStorage<360> g_readings;
constexpr float kRangeMax = 12.0f;

void build_room() {
  g_grid.configure(160, 120, 0.05f, 0.0f, 0.0f, est::kFreeCell);
  g_grid.fill_rect(0, 0, 159, 0, est::kOccupiedCell);
  g_grid.fill_rect(0, 119, 159, 119, est::kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 119, est::kOccupiedCell);
  g_grid.fill_rect(159, 0, 159, 119, est::kOccupiedCell);
  g_grid.fill_rect(100, 0, 101, 70, est::kOccupiedCell);
  g_grid.fill_rect(30, 30, 45, 40, est::kOccupiedCell);
  g_grid.fill_rect(120, 90, 130, 100, est::kOccupiedCell);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  REQUIRE(g_table.build(g_grid.grid(), est::GridRayCaster(g_grid.grid()), 32, kRangeMax) ==
          est::HeadingRangeTableStatus::ok);
}

// A 360 x 1 deg scan cast exactly from `truth`, with a few max readings; kept every `stride`-th beam.
est::ScanBeams make_scan(const est::Pose2& truth, std::int32_t stride) {
  const est::GridRayCaster exact(g_grid.grid());
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 360.0f, 360, 0.05f, kRangeMax};
  float ranges[360];
  est::Rng rng(3u);
  for (int k = 0; k < 360; ++k) {
    const float a = truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    ranges[k] = exact.cast(truth.x, truth.y, std::cos(a), std::sin(a), kRangeMax) + rng.uniform(-0.03f, 0.03f);
  }
  ranges[17] = __builtin_inff();
  ranges[200] = 15.0f;
  ranges[41] = 0.07f;  // a short reading (an obstacle not in the map)
  REQUIRE(g_scan.prepare(layout, ranges, stride) == est::ScanStatus::ok);
  return g_scan.beams();
}

// The exact sum over the beams of log p(z_k | z*_k), in double, from the same per-beam float densities and z* the
// function uses (each floored at 1e-30 as the product is).
double reference(const est::ScanBeams& z, const est::BeamBearings& bearings, const est::Pose2& x,
                 const est::HeadingRangeTable& table, const est::BeamRangeFinderModel& model) {
  const est::SensorFrame f = est::sensor_frame(x, {});
  const float heading_bins = est::fmath::normalize_angle(x.theta) * table.bins_per_rad();
  double sum = 0.0;
  for (int k = 0; k < z.count; ++k) {
    const float dx = f.c * z.ux[k] - f.s * z.uy[k];
    const float dy = f.s * z.ux[k] + f.c * z.uy[k];
    const float z_exp = table.cast_bins(f.x, f.y, dx, dy, heading_bins + bearings.bins_of_beam[k], kRangeMax);
    const float d = model.density(z.is_max[k] ? kRangeMax : z.range[k], z_exp);
    sum += std::log(double(d > 1e-30f ? d : 1e-30f));
  }
  return sum;
}

double ulp(double y) { return std::ldexp(1.0, std::ilogb(std::fabs(y) > 1e-30 ? y : 1e-30) - 23); }

}  // namespace

TEST_CASE("beam model table path with prepared readings: the exact sum of log densities within K 2^-24 + 2 ULP",
          "[beam_range_finder_model_table]") {
  build_room();
  const est::HeadingRangeTable table = g_table.view();
  est::BeamRangeFinderModel model;
  est::BeamModelParams bp;
  bp.range_max = kRangeMax;
  REQUIRE(model.configure(bp) == est::SensorModelStatus::ok);
  const est::Pose2 truth{2.6f, 3.1f, 0.4f};
  for (std::int32_t stride : {1, 6}) {
    const est::ScanBeams z = make_scan(truth, stride);
    REQUIRE(g_bearings.prepare(z, table));
    REQUIRE(g_readings.prepare(z, model));
    est::Rng rng(11u);
    double worst = 0.0, worst_vs_log_sum = 0.0;
    for (int i = 0; i < 300; ++i) {
      // Particles around the truth, and some anywhere in the room (inside obstacles too: z* = 0).
      est::Pose2 x{truth.x + rng.uniform(-0.4f, 0.4f), truth.y + rng.uniform(-0.4f, 0.4f),
                   truth.theta + rng.uniform(-0.15f, 0.15f)};
      if (i % 5 == 0) x = {rng.uniform(0.0f, 8.0f), rng.uniform(0.0f, 6.0f), rng.uniform(-est::kPi, est::kPi)};
      const float fast = est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), x, {}, table, model);
      const float again = est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), x, {}, table, model);
      REQUIRE(std::memcmp(&fast, &again, sizeof fast) == 0);
      const double exact = reference(z, g_bearings.view(), x, table, model);
      const double bound = z.count * std::ldexp(1.0, -24) * (1.0 + std::ldexp(1.0, -23)) + 2.0 * ulp(exact);
      INFO("particle " << i << " K " << z.count << " exact " << exact << " fast " << fast);
      REQUIRE(std::isfinite(fast));
      REQUIRE(std::fabs(double(fast) - exact) <= bound);
      worst = std::max(worst, std::fabs(double(fast) - exact) / bound);
      // The per-beam-log overload (a float sum of K logs) agrees within its own rounding: 1e-5 relative.
      const float per_beam = est::beam_range_finder_model(z, g_bearings.view(), x, {}, table, model);
      worst_vs_log_sum = std::max(worst_vs_log_sum, std::fabs(double(per_beam) - double(fast)) / std::fabs(exact));
      REQUIRE(std::fabs(double(per_beam) - double(fast)) <= 1e-5 * std::fabs(exact) + 1e-4);
    }
    std::printf("beam model table path, K = %d: worst |fast - exact| %.2f of the bound; |per-beam logs - fast| <= "
                "%.1e relative\n",
                z.count, worst, worst_vs_log_sum);
  }
}

TEST_CASE("beam model table path with prepared readings refuses what does not match, with the stated floor",
          "[beam_range_finder_model_table]") {
  build_room();
  const est::HeadingRangeTable table = g_table.view();
  est::BeamRangeFinderModel model;
  est::BeamModelParams bp;
  bp.range_max = kRangeMax;
  REQUIRE(model.configure(bp) == est::SensorModelStatus::ok);
  const est::Pose2 truth{2.6f, 3.1f, 0.4f};
  const est::ScanBeams z = make_scan(truth, 1);
  REQUIRE(g_bearings.prepare(z, table));
  REQUIRE(g_readings.prepare(z, model));
  const float floor_all = static_cast<float>(z.count) * est::kBeamLogDensityFloor;
  const float ok = est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), truth, {}, table, model);
  CHECK(ok > floor_all);
  // The truth explains the scan better than a pose 0.3 m off.
  CHECK(ok > est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), {truth.x + 0.3f, truth.y, 0.4f},
                                          {}, table, model));
  // Non-finite pose, readings for another configuration, readings for another scan, unprepared readings.
  CHECK(est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), {__builtin_nanf(""), 1.0f, 0.0f}, {},
                                     table, model) == floor_all);
  est::BeamRangeFinderModel other;
  bp.sigma_hit = 0.25f;
  REQUIRE(other.configure(bp) == est::SensorModelStatus::ok);
  CHECK(est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), truth, {}, table, other) == floor_all);
  static est::BeamReadingsStorage<360> unprepared;
  CHECK(est::beam_range_finder_model(z, g_bearings.view(), unprepared.view(), truth, {}, table, model) == floor_all);
  static est::PreparedScan<360> sixty;
  static est::BeamReadingsStorage<360> readings60;
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 60.0f, 60, 0.05f, kRangeMax};
  float ranges[60];
  for (float& r : ranges) r = 2.0f;
  REQUIRE(sixty.prepare(layout, ranges) == est::ScanStatus::ok);
  REQUIRE(readings60.prepare(sixty.beams(), model));
  CHECK(est::beam_range_finder_model(z, g_bearings.view(), readings60.view(), truth, {}, table, model) == floor_all);
  // A pose off the map: z* = 0 on every beam, finite.
  CHECK(std::isfinite(
      est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(), {-5.0f, -5.0f, 0.0f}, {}, table, model)));
}
