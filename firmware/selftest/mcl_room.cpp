#include "mcl_room.hpp"

#include "est/map/distance_transform.hpp"

namespace est::selftest {
namespace {

MclRoomGrid g_grid;
DistanceTransformStorage<64, 48> g_edt;
LikelihoodFieldGridStorage<64, 48> g_field_grid;
LikelihoodField g_field;

}  // namespace

MclRoom mcl_room(void (*furnish)(MclRoomGrid&)) {
  g_grid.configure(64, 48, 0.1f, 0.0f, 0.0f, kFreeCell);
  g_grid.fill_rect(0, 0, 63, 0, kOccupiedCell);
  g_grid.fill_rect(0, 47, 63, 47, kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 47, kOccupiedCell);
  g_grid.fill_rect(63, 0, 63, 47, kOccupiedCell);
  furnish(g_grid);
  g_edt.build(g_grid.grid());
  const OccupancyGrid grid = g_grid.grid();
  LikelihoodFieldParams lp;
  lp.z_hit = 0.85f;
  lp.z_rand = 0.10f;
  lp.range_max = 6.0f;
  g_field.configure(lp, grid, g_edt.view());
  g_field_grid.build(g_field, grid);
  return MclRoom{grid, g_field, g_field_grid.view(), DistanceTransformRayCaster(grid, g_edt.view()),
                 FreeSpaceSampler(grid, g_edt.view(), 0.2f)};
}

}  // namespace est::selftest
