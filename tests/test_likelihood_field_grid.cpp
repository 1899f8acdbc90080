#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "world/office_map.hpp"

namespace {

est::OccupancyGridStorage<400, 300> g_grid;
est::DistanceTransformStorage<400, 300> g_edt;
est::LikelihoodFieldGridStorage<400, 300> g_table;
est::PreparedScan<360> g_scan;
est::LikelihoodField g_field;

std::uint32_t bits(float v) {
  std::uint32_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("the batched likelihood field equals the scalar model bit for bit, particles off the map and NaN included",
          "[likelihood_field_grid]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  est::LikelihoodFieldParams p;
  p.range_max = 12.0f;
  p.max_distance = 2.0f;
  REQUIRE(g_field.configure(p, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  REQUIRE(g_table.build(g_field, g_grid.grid()) == est::MapStatus::ok);

  // A 360-beam scan from a pose in the corridor, with max readings (range 12 m) and two rejected readings.
  const est::DistanceTransformRayCaster caster(g_grid.grid(), g_edt.view());
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 360.0f, 360, 0.05f, 12.0f};
  std::vector<float> ranges(360);
  for (int k = 0; k < 360; ++k) {
    const float a = layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    ranges[static_cast<std::size_t>(k)] = caster.cast(7.0f, 7.3f, std::cos(a), std::sin(a), 12.0f);
  }
  ranges[3] = std::numeric_limits<float>::quiet_NaN();
  ranges[4] = 0.01f;
  REQUIRE(g_scan.prepare(layout, ranges.data()) == est::ScanStatus::ok);
  REQUIRE(g_scan.counters().max_readings > 0);
  const est::ScanBeams z = g_scan.beams();

  // 1000 particles (not a multiple of the block): most near the pose, some far off the map, some non-finite.
  const std::uint32_t n = 1000;
  std::vector<float> x(n), y(n), th(n), out(n);
  est::Rng rng(4u);
  for (std::uint32_t i = 0; i < n; ++i) {
    x[i] = rng.uniform(-3.0f, 23.0f);
    y[i] = rng.uniform(-3.0f, 18.0f);
    th[i] = rng.uniform(-4.0f, 4.0f);
  }
  x[10] = std::numeric_limits<float>::quiet_NaN();
  th[11] = std::numeric_limits<float>::infinity();
  th[12] = -0.0f;
  x[12] = 7.0f;
  y[12] = 7.3f;
  th[13] = 250.0f;  // beyond the vectorized sincos's range: the scalar one's lane
  th[14] = -1e30f;
  // A rotated mount, and an unrotated one (where the batch reuses the robot's sincos for the sensor).
  for (const est::Pose2 mount : {est::Pose2{0.1f, 0.02f, 0.05f}, est::Pose2{0.1f, 0.02f, 0.0f}}) {
    est::likelihood_field_range_finder_model_batch(z, x.data(), y.data(), th.data(), n, mount, g_table.view(),
                                                   out.data());
    int differ = 0;
    for (std::uint32_t i = 0; i < n; ++i)
      differ += bits(out[i]) == bits(est::likelihood_field_range_finder_model(z, {x[i], y[i], th[i]}, mount, g_field))
                    ? 0
                    : 1;
    CHECK(differ == 0);
    CHECK(std::isfinite(out[10]));
    CHECK(out[10] == out[11]);  // the floor for every beam that is not a max reading
  }
}

TEST_CASE("the per-cell table is refused for a map larger than its storage, and costs 2 bytes per padded cell",
          "[likelihood_field_grid]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  REQUIRE(g_field.configure({}, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  static est::LikelihoodFieldGridStorage<100, 100> small;
  CHECK(small.build(g_field, g_grid.grid()) == est::MapStatus::too_large);
  CHECK(est::LikelihoodFieldGridStorage<400, 300>::kBytes == 2u * 402u * 302u);
  est::LikelihoodField unconfigured;
  CHECK(g_table.build(unconfigured, g_grid.grid()) == est::MapStatus::empty);
}

TEST_CASE("the quantized terms are within half a step of the field's float terms, and the pad is the outside term",
          "[likelihood_field_grid]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  REQUIRE(g_field.configure({}, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);
  REQUIRE(g_table.build(g_field, g_grid.grid()) == est::MapStatus::ok);
  const est::LikelihoodFieldGrid v = g_table.view();
  const est::OccupancyGrid g = g_grid.grid();
  const double peak = double(g_field.log_term_max());
  double worst = 0.0;
  for (std::int32_t cy = 0; cy < g.height(); cy += 3)
    for (std::int32_t cx = 0; cx < g.width(); cx += 3) {
      const double term = double(g_field.log_term_at(g.cell_center_x(cx), g.cell_center_y(cy)));
      const double q = peak - double(v.cells()[static_cast<std::uint32_t>(cy + 1) * v.stride() +
                                               static_cast<std::uint32_t>(cx + 1)]) / 256.0;
      worst = std::max(worst, std::fabs(q - term));
    }
  CHECK(worst <= 1.0 / 512.0 + 1e-6);
  const std::uint16_t outside = v.cells()[0];
  CHECK(double(peak - outside / 256.0) ==
        Approx(double(g_field.log_term_at(g.origin_x() - 1.0f, g.origin_y() - 1.0f))).margin(1.0 / 512.0 + 1e-6));
  for (std::uint32_t ix = 0; ix < v.stride(); ++ix) {
    CHECK(v.cells()[ix] == outside);
    CHECK(v.cells()[(v.rows() - 1u) * v.stride() + ix] == outside);
  }
  for (std::uint32_t iy = 0; iy < v.rows(); ++iy) {
    CHECK(v.cells()[iy * v.stride()] == outside);
    CHECK(v.cells()[iy * v.stride() + v.stride() - 1u] == outside);
  }
}
