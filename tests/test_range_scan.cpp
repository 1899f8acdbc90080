#include <catch2/catch.hpp>

#include <cmath>

#include "est/sensor/range_scan.hpp"

namespace {
est::PreparedScan<400> g_scan;
}

TEST_CASE("a 360 x 1 deg scan keeps every beam with its bearing", "[range_scan]") {
  float ranges[360];
  for (int k = 0; k < 360; ++k) ranges[k] = 1.0f + 0.01f * static_cast<float>(k);
  const est::ScanLayout layout{-est::kPi, est::kPi / 180.0f, 360, 0.0f, 10.0f};
  REQUIRE(g_scan.prepare(layout, ranges) == est::ScanStatus::ok);
  const est::ScanBeams b = g_scan.beams();
  REQUIRE(b.count == 360);
  for (int k = 0; k < 360; k += 37) {
    const double a = -M_PI + k * M_PI / 180.0;
    CHECK(b.ux[k] == Approx(std::cos(a)).margin(2e-6));
    CHECK(b.uy[k] == Approx(std::sin(a)).margin(2e-6));
    CHECK(b.range[k] == ranges[k]);
  }
}

TEST_CASE("subsampling keeps every s-th beam from the first one", "[range_scan]") {
  float ranges[181];
  for (float& r : ranges) r = 2.0f;
  const est::ScanLayout layout{-est::kHalfPi, est::kPi / 180.0f, 181, 0.0f, 30.0f};
  REQUIRE(g_scan.prepare(layout, ranges, 10) == est::ScanStatus::ok);
  CHECK(g_scan.beams().count == 19);  // 0, 10, ..., 180
  CHECK(g_scan.counters().skipped_stride == 162);
  // The last kept beam is k = 180: bearing +90 deg.
  CHECK(g_scan.beams().uy[18] == Approx(1.0f).margin(1e-6));
  REQUIRE(g_scan.prepare(layout, ranges, 10, 5) == est::ScanStatus::ok);
  CHECK(g_scan.beams().count == 18);  // 5, 15, ..., 175
  CHECK(g_scan.prepare(layout, ranges, 0) == est::ScanStatus::bad_layout);
}

TEST_CASE("NaN, -inf and negative readings are rejected and counted; +inf and max readings are max readings",
          "[range_scan]") {
  const float nan = __builtin_nanf(""), inf = __builtin_inff();
  const float ranges[8] = {1.0f, nan, inf, -inf, -0.5f, 0.05f, 30.0f, 45.0f};
  const est::ScanLayout layout{0.0f, 0.1f, 8, 0.1f, 30.0f};
  REQUIRE(g_scan.prepare(layout, ranges) == est::ScanStatus::ok);
  const est::ScanCounters& c = g_scan.counters();
  CHECK(c.kept == 4);
  CHECK(c.rejected_nonfinite == 2);  // NaN and -inf
  CHECK(c.rejected_below_min == 2);  // -0.5 and 0.05 < range_min
  CHECK(c.max_readings == 3);        // +inf (no return, REP 117), 30 and 45
  const est::ScanBeams b = g_scan.beams();
  CHECK(b.is_max[0] == 0);
  CHECK(b.is_max[1] == 1);
  CHECK(b.range[1] == 30.0f);  // +inf clamped to range_max
  CHECK(b.range[3] == 30.0f);  // 45 clamped
}

TEST_CASE("bad layouts and scans with nothing usable are refused, leaving an empty scan", "[range_scan]") {
  const float nan = __builtin_nanf("");
  const float ranges[3] = {nan, nan, -1.0f};
  CHECK(g_scan.prepare({0.0f, 0.1f, 3, 0.0f, 10.0f}, ranges) == est::ScanStatus::no_beams);
  CHECK(g_scan.beams().count == 0);
  CHECK(g_scan.prepare({0.0f, 0.1f, 0, 0.0f, 10.0f}, ranges) == est::ScanStatus::bad_layout);
  CHECK(g_scan.prepare({nan, 0.1f, 3, 0.0f, 10.0f}, ranges) == est::ScanStatus::bad_layout);
  CHECK(g_scan.prepare({0.0f, 0.1f, 3, 5.0f, 5.0f}, ranges) == est::ScanStatus::bad_layout);
  static est::PreparedScan<4> small;
  float many[10] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  CHECK(small.prepare({0.0f, 0.1f, 10, 0.0f, 10.0f}, many) == est::ScanStatus::too_many_beams);
  CHECK(small.beams().count == 0);
  CHECK(small.prepare({0.0f, 0.1f, 10, 0.0f, 10.0f}, many, 3) == est::ScanStatus::ok);  // 4 beams fit
}

TEST_CASE("the sensor frame composes the robot pose with the mount", "[range_scan]") {
  const est::SensorFrame f = est::sensor_frame({1.0f, 2.0f, est::kHalfPi}, {0.5f, 0.1f, est::kPi});
  CHECK(f.x == Approx(1.0f - 0.1f).margin(1e-6));
  CHECK(f.y == Approx(2.0f + 0.5f).margin(1e-6));
  CHECK(f.c == Approx(0.0f).margin(1e-6));
  CHECK(f.s == Approx(-1.0f).margin(1e-6));
}
