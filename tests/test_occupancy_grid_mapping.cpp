// Occupancy grid mapping with known poses (est/map/occupancy_grid_mapping.hpp, Thrun tables 9.1 and 9.2): a beam
// frees the cells it crosses and marks its end point, max-range readings only free, evidence adds in log odds and
// is clamped, and the map reads back with the ROS thresholds.
#include <catch2/catch.hpp>

#include <cmath>

#include "est/map/occupancy_grid_mapping.hpp"

namespace {

constexpr std::int32_t kW = 40, kH = 20;
float g_cells[kW * kH];
est::OccupancyGridStorage<kW, kH> g_map;

// A 40 x 20 grid of 0.1 m cells with its corner at (0, 0).
est::LogOddsGrid fresh_grid() {
  est::LogOddsGrid g(g_cells, kW, kH, 0.1f, 0.0f, 0.0f);
  g.reset();
  return g;
}

// One beam straight ahead (+x) from (x, 1.05).
void scan_ahead(est::LogOddsGrid& g, float x, float range, float range_max, const est::InverseRangeSensorParams& p,
                est::MappingCounters& c) {
  const est::ScanLayout layout{0.0f, 0.01f, 1, 0.02f, range_max};
  g.update({x, 1.05f, 0.0f}, {}, layout, &range, p, c);
}

}  // namespace

TEST_CASE("a beam frees the cells before its end point and marks the end point's cell", "[occupancy_grid_mapping]") {
  est::LogOddsGrid g = fresh_grid();
  est::InverseRangeSensorParams p;
  est::MappingCounters c;
  scan_ahead(g, 0.05f, 2.0f, 10.0f, p, c);  // end point at x = 2.05: cell 20
  CHECK(c.scans == 1);
  CHECK(c.beams_hit == 1);
  for (std::int32_t cx = 0; cx < 20; ++cx) CHECK(g.at(cx, 10) == Approx(p.l_free));
  CHECK(g.at(20, 10) == Approx(p.l_occ));
  CHECK(g.at(21, 10) == 0.0f);  // behind the obstacle: l_0, unknown
  CHECK(g.at(5, 11) == 0.0f);   // beside the beam
  CHECK(c.cells_updated == 21);
  CHECK(est::LogOddsGrid::to_cell(g.at(21, 10)) == est::kUnknownCell);
  CHECK(est::LogOddsGrid::to_cell(g.at(20, 10)) == 70);
  CHECK(est::LogOddsGrid::to_cell(g.at(3, 10)) == 40);
}

TEST_CASE("evidence adds in log odds, is clamped, and reads back as occupied and free", "[occupancy_grid_mapping]") {
  est::LogOddsGrid g = fresh_grid();
  est::InverseRangeSensorParams p;
  est::MappingCounters c;
  for (int i = 0; i < 30; ++i) scan_ahead(g, 0.05f, 2.0f, 10.0f, p, c);
  CHECK(g.at(20, 10) == Approx(p.l_max));
  CHECK(g.at(10, 10) == Approx(p.l_min));
  for (int i = 0; i < 2; ++i) scan_ahead(g, 0.05f, 3.0f, 10.0f, p, c);  // the obstacle moved away: freed again
  CHECK(g.at(20, 10) == Approx(p.l_max + 2.0f * p.l_free));
  REQUIRE(g.to_occupancy(g_map));
  const est::OccupancyGrid m = g_map.grid();
  CHECK(m.width() == kW);
  CHECK(m.resolution() == Approx(0.1f));
  CHECK(m.classify(20, 10) == est::CellClass::occupied);
  CHECK(m.classify(30, 10) == est::CellClass::occupied);  // the new end point after two scans: 2 l_occ
  CHECK(m.classify(10, 10) == est::CellClass::free);
  CHECK(m.classify(10, 15) == est::CellClass::unknown);
}

TEST_CASE("max-range readings and hits beyond the mapped range free space without marking a wall",
          "[occupancy_grid_mapping]") {
  est::LogOddsGrid g = fresh_grid();
  est::InverseRangeSensorParams p;
  p.hit_range_max = 1.0f;
  p.free_range_max = 1.5f;
  est::MappingCounters c;
  scan_ahead(g, 0.05f, 10.0f, 10.0f, p, c);  // a max reading: free up to 1.5 m
  CHECK(c.beams_free == 1);
  CHECK(g.at(14, 10) == Approx(p.l_free));
  CHECK(g.at(15, 10) == Approx(p.l_free));  // the cell holding the 1.55 m end of the free stretch
  CHECK(g.at(16, 10) == 0.0f);
  est::LogOddsGrid h = fresh_grid();
  scan_ahead(h, 0.05f, 1.2f, 10.0f, p, c);  // a hit beyond hit_range_max: free up to it, no wall
  CHECK(c.beams_free == 2);
  CHECK(h.at(12, 10) == Approx(p.l_free));
  CHECK(h.at(13, 10) == 0.0f);
}

TEST_CASE("unusable readings, poses off the map and rays leaving it are handled and counted",
          "[occupancy_grid_mapping]") {
  est::LogOddsGrid g = fresh_grid();
  est::InverseRangeSensorParams p;
  est::MappingCounters c;
  const float readings[3] = {__builtin_nanf(""), 0.01f, 1.0f};
  const est::ScanLayout layout{0.0f, 0.01f, 3, 0.02f, 10.0f};
  g.update({-5.0f, 1.05f, 0.0f}, {}, layout, readings, p, c);  // the sensor off the map
  CHECK(c.beams_skipped == 3);
  CHECK(c.cells_updated == 0);
  scan_ahead(g, 3.55f, 5.0f, 10.0f, p, c);  // the end point beyond the map's edge at x = 4
  CHECK(g.at(39, 10) == Approx(p.l_free));
  CHECK(c.beams_hit == 1);
  // The mount turns the beam: a sensor at 90 degrees looks along +y.
  est::LogOddsGrid h = fresh_grid();
  const float r = 0.5f;
  const est::ScanLayout one{0.0f, 0.01f, 1, 0.02f, 10.0f};
  h.update({1.05f, 0.05f, 0.0f}, {0.0f, 0.0f, 1.5707963f}, one, &r, p, c);
  CHECK(h.at(10, 5) == Approx(p.l_occ));
  CHECK(h.at(10, 2) == Approx(p.l_free));
}
