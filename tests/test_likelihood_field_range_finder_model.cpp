#include <catch2/catch.hpp>

#include <cmath>

#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "world/office_map.hpp"

namespace {

est::OccupancyGridStorage<400, 300> g_grid;
est::DistanceTransformStorage<400, 300> g_edt;
est::PreparedScan<360> g_scan;
est::LikelihoodField g_field;

double reference_term(double d, const est::LikelihoodFieldParams& p) {
  const double s = p.sigma_hit, z_hit = p.z_hit, z_rand = p.z_rand, zm = p.range_max;
  return std::log(z_hit * std::exp(-0.5 * d * d / (s * s)) / (s * std::sqrt(2.0 * M_PI)) + z_rand / zm);
}

// A 20 m x 5 m open map with one wall column at x in [10, 10.05).
void wall_map() {
  REQUIRE(g_grid.configure(400, 100, 0.05f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(200, 0, 200, 99, est::kOccupiedCell);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
}

}  // namespace

TEST_CASE("likelihood field: along a beam facing a wall the density integrates to z_hit + z_rand", "[likelihood_field]") {
  wall_map();
  est::LikelihoodFieldParams p;
  p.range_max = 15.0f;
  REQUIRE(g_field.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  // Beam from (2.025, 2.525) along +x through cell centres; z in [0, 15).
  const int n = 150000;
  const double h = 15.0 / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double z = (i + 0.5) * h;
    sum += std::exp(double(g_field.log_term_at(static_cast<float>(2.025 + z), 2.525f))) * h;
  }
  // Tolerance 2e-3: the Gaussian is sampled per cell (0.05 m = sigma / 4) and its tails beyond 2 m are capped.
  const double z_hit = p.z_hit, z_rand = p.z_rand, z_max = p.z_max;
  CHECK(sum == Approx(z_hit + z_rand).margin(2e-3));
  CHECK(sum + z_max == Approx(1.0).margin(2e-3));
}

TEST_CASE("likelihood field terms match the double-precision formula of table 6.3", "[likelihood_field]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  est::LikelihoodFieldParams p;
  p.z_hit = 0.8f;
  p.z_rand = 0.15f;
  p.sigma_hit = 0.1f;
  p.range_max = 12.0f;
  p.max_distance = 1.0f;
  REQUIRE(g_field.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  CHECK(g_field.bucket_shift() == 0);
  const est::OccupancyGrid g = g_grid.grid();
  est::Rng rng(3u);
  for (int i = 0; i < 2000; ++i) {
    const float x = rng.uniform(-1.0f, 21.0f), y = rng.uniform(-1.0f, 16.0f);
    std::int32_t cx = 0, cy = 0;
    double d = 1.0;  // off the map: the cap
    if (g.world_to_cell(x, y, cx, cy)) {
      // Brute force over the occupied cells near the end point, floored to 1/16 cell like the transform.
      double best = 1e9;
      for (std::int32_t j = cy - 25; j <= cy + 25; ++j)
        for (std::int32_t k = cx - 25; k <= cx + 25; ++k)
          if (g.is_occupied(k, j)) best = std::min(best, std::hypot(double(k - cx), double(j - cy)));
      d = std::min(1.0, std::floor(16.0 * best + 1e-9) / 16.0 * 0.05);
    }
    INFO("end point " << x << ", " << y);
    CHECK(double(g_field.log_term_at(x, y)) == Approx(reference_term(d, p)).margin(2e-5));
  }
}

TEST_CASE("likelihood field scan log-likelihood skips max readings and prefers the true pose", "[likelihood_field]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  est::LikelihoodFieldParams p;
  p.range_max = 6.0f;
  REQUIRE(g_field.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  const est::DistanceTransformRayCaster caster(g_grid.grid(), g_edt.view());
  const est::Pose2 truth{11.0f, 4.0f, -2.0f};
  const est::Pose2 mount{0.1f, 0.05f, 0.0f};
  const est::ScanLayout layout{-est::kPi, est::kPi / 180.0f, 360, 0.0f, 6.0f};
  float ranges[360];
  const est::SensorFrame f = est::sensor_frame(truth, mount);
  for (int k = 0; k < 360; ++k) {
    const double a = std::atan2(double(f.s), double(f.c)) + double(layout.angle_min) + k * double(layout.angle_increment);
    ranges[k] = caster.cast(f.x, f.y, static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 6.0f);
  }
  REQUIRE(g_scan.prepare(layout, ranges, 3) == est::ScanStatus::ok);
  const est::ScanBeams b = g_scan.beams();
  REQUIRE(g_scan.counters().max_readings > 0);  // the 6 m cap leaves some beams without return
  double by_hand = 0.0;
  int hits = 0;
  for (int k = 0; k < b.count; ++k) {
    if (b.is_max[k]) continue;
    const float ex = f.x + b.range[k] * (f.c * b.ux[k] - f.s * b.uy[k]);
    const float ey = f.y + b.range[k] * (f.s * b.ux[k] + f.c * b.uy[k]);
    by_hand += double(g_field.log_term_at(ex, ey));
    ++hits;
  }
  const float l = est::likelihood_field_range_finder_model(b, truth, mount, g_field);
  // The model sums terms quantized to 1/256 nat (each within 1/512 of the float term) at end points computed in
  // cell units (a cell boundary may fall the other way): within half a step per beam, and a few boundary beams.
  CHECK(std::fabs(double(l) - by_hand) <= hits / 512.0 + 0.05);
  CHECK(l > est::likelihood_field_range_finder_model(b, {11.2f, 4.0f, -2.0f}, mount, g_field) + 10.0f);
  CHECK(l > est::likelihood_field_range_finder_model(b, {11.0f, 4.0f, -1.9f}, mount, g_field) + 10.0f);
  const int not_max = b.count - g_scan.counters().max_readings;
  CHECK(est::likelihood_field_range_finder_model(b, {0.0f, __builtin_inff(), 0.0f}, mount, g_field) ==
        Approx(static_cast<float>(not_max) * est::kBeamLogDensityFloor));
}

TEST_CASE("likelihood field coarsens its table for long max distances within half a bucket", "[likelihood_field]") {
  wall_map();
  est::LikelihoodFieldParams p;
  p.sigma_hit = 1.0f;
  p.max_distance = 12.0f;  // 3840 units of 1/16 cell: 4 units per entry
  REQUIRE(g_field.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  CHECK(g_field.bucket_shift() == 2);
  CHECK(g_field.table_entries() <= est::kLikelihoodFieldTableSize);
  for (float x = 2.0f; x < 18.0f; x += 0.37f) {
    const double d = std::min(12.0, std::fabs(std::floor(double(x) / 0.05) - 200.0) * 0.05);
    // Half a bucket is 2/16 cell = 6.25 mm; the slope of the log term is at most d / sigma^2 < 12 per metre.
    CHECK(double(g_field.log_term_at(x, 2.5f)) == Approx(reference_term(d, p)).margin(12.0 * 0.00625 + 1e-5));
  }
}

TEST_CASE("likelihood field parameters are validated", "[likelihood_field]") {
  wall_map();
  est::LikelihoodField f;
  est::LikelihoodFieldParams p;
  p.z_hit = 0.5f;
  CHECK(f.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::bad_weights);
  p = {};
  p.max_distance = 0.0f;
  CHECK(f.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::bad_distance);
  p = {};
  p.sigma_hit = -1.0f;
  CHECK(f.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::bad_sigma);
  p = {};
  CHECK(f.configure(p, g_grid.grid(), est::DistanceTransform{}) == est::SensorModelStatus::not_ready);
  CHECK_FALSE(f.ready());
}
