#include <catch2/catch.hpp>

#include "est/map/occupancy_grid.hpp"

namespace {
est::OccupancyGridStorage<16, 8> g_storage;
}

TEST_CASE("configure rejects sizes beyond the capacity and bad geometry, and changes nothing then", "[occupancy_grid]") {
  auto& g = g_storage;
  REQUIRE(g.configure(10, 5, 0.1f, -1.0f, 2.0f, est::kFreeCell) == est::MapStatus::ok);
  CHECK(g.configure(17, 5, 0.1f, 0.0f, 0.0f) == est::MapStatus::too_large);
  CHECK(g.configure(16, 9, 0.1f, 0.0f, 0.0f) == est::MapStatus::too_large);
  CHECK(g.configure(0, 5, 0.1f, 0.0f, 0.0f) == est::MapStatus::empty);
  CHECK(g.configure(4, 4, 0.0f, 0.0f, 0.0f) == est::MapStatus::bad_resolution);
  CHECK(g.configure(4, 4, -0.1f, 0.0f, 0.0f) == est::MapStatus::bad_resolution);
  CHECK(g.configure(4, 4, 0.1f, __builtin_nanf(""), 0.0f) == est::MapStatus::bad_origin);
  CHECK(g.configure(4, 4, 0.1f, 0.0f, 0.0f, 0, est::CellThresholds{50, 60}) == est::MapStatus::bad_thresholds);
  const est::OccupancyGrid v = g.grid();
  CHECK(v.width() == 10);
  CHECK(v.height() == 5);
  CHECK(v.origin_x() == -1.0f);
}

TEST_CASE("world to cell follows the corner-origin convention and rejects points off the map", "[occupancy_grid]") {
  auto& g = g_storage;
  REQUIRE(g.configure(10, 5, 0.5f, -1.0f, 2.0f, est::kFreeCell) == est::MapStatus::ok);
  const est::OccupancyGrid v = g.grid();
  std::int32_t cx = -7, cy = -7;
  REQUIRE(v.world_to_cell(-1.0f, 2.0f, cx, cy));
  CHECK((cx == 0 && cy == 0));
  REQUIRE(v.world_to_cell(-0.51f, 2.49f, cx, cy));
  CHECK((cx == 0 && cy == 0));
  REQUIRE(v.world_to_cell(-0.5f, 2.5f, cx, cy));
  CHECK((cx == 1 && cy == 1));
  REQUIRE(v.world_to_cell(3.99f, 4.49f, cx, cy));
  CHECK((cx == 9 && cy == 4));
  cx = cy = -7;
  CHECK_FALSE(v.world_to_cell(4.0f, 3.0f, cx, cy));   // x = origin + width * res is outside
  CHECK_FALSE(v.world_to_cell(0.0f, 4.5f, cx, cy));
  CHECK_FALSE(v.world_to_cell(-1.01f, 3.0f, cx, cy));
  CHECK_FALSE(v.world_to_cell(__builtin_nanf(""), 3.0f, cx, cy));
  CHECK_FALSE(v.world_to_cell(__builtin_inff(), 3.0f, cx, cy));
  CHECK((cx == -7 && cy == -7));
  CHECK(v.cell_center_x(1) == -0.25f);
  CHECK(v.cell_center_y(0) == 2.25f);
  // Round trip through every cell centre.
  for (std::int32_t y = 0; y < 5; ++y)
    for (std::int32_t x = 0; x < 10; ++x) {
      REQUIRE(v.world_to_cell(v.cell_center_x(x), v.cell_center_y(y), cx, cy));
      CHECK((cx == x && cy == y));
    }
}

TEST_CASE("cells classify as free, occupied or unknown with the ROS thresholds", "[occupancy_grid]") {
  auto& g = g_storage;
  REQUIRE(g.configure(8, 2, 0.1f, 0.0f, 0.0f) == est::MapStatus::ok);
  const std::uint8_t values[8] = {0, 19, 20, 64, 65, 100, 101, est::kUnknownCell};
  const est::CellClass expect[8] = {est::CellClass::free,     est::CellClass::free,     est::CellClass::unknown,
                                    est::CellClass::unknown,  est::CellClass::occupied, est::CellClass::occupied,
                                    est::CellClass::unknown,  est::CellClass::unknown};
  for (std::int32_t i = 0; i < 8; ++i) REQUIRE(g.set(i, 0, values[i]));
  const est::OccupancyGrid v = g.grid();
  for (std::int32_t i = 0; i < 8; ++i) {
    INFO("value " << int(values[i]));
    CHECK(v.classify(i, 0) == expect[i]);
    CHECK(v.is_occupied(i, 0) == (expect[i] == est::CellClass::occupied));
  }
  // Fresh cells are unknown; outside the map is unknown and never occupied.
  CHECK(v.classify(0, 1) == est::CellClass::unknown);
  CHECK(v.classify(-1, 0) == est::CellClass::unknown);
  CHECK(v.classify(8, 0) == est::CellClass::unknown);
  CHECK_FALSE(v.is_occupied(8, 0));
  CHECK_FALSE(g.set(8, 0, 100));  // out-of-range writes are refused
  CHECK_FALSE(g.set(0, -1, 100));
}

TEST_CASE("fill_rect clips to the map", "[occupancy_grid]") {
  auto& g = g_storage;
  REQUIRE(g.configure(6, 4, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g.fill_rect(-3, 2, 10, 9, est::kOccupiedCell);
  int occupied = 0;
  for (std::int32_t y = 0; y < 4; ++y)
    for (std::int32_t x = 0; x < 6; ++x) occupied += g.grid().is_occupied(x, y) ? 1 : 0;
  CHECK(occupied == 12);
  CHECK(g.grid().is_occupied(0, 2));
  CHECK_FALSE(g.grid().is_occupied(0, 1));
}
