#pragma once
// The office world of the scenarios: the synthetic office (sim_host/maps/office_map.hpp: 20 m x 15 m at 0.05 m,
// rooms, corridor, doors, furniture, a pillar, a diagonal wall; asymmetric), its distance transform, 16 landmarks
// (posts with signatures 1..16, placed without symmetry) and a closed route of 24.7 m through the corridor, the
// north-east room, the door between the north rooms and the north-west room. Built once, deterministically.
#include "est/map/distance_transform.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "world/office_map.hpp"
#include "world/route.hpp"

namespace est::sim {

struct OfficeWorld {
  OccupancyGridStorage<kOfficeWidth, kOfficeHeight> grid_storage;
  DistanceTransformStorage<kOfficeWidth, kOfficeHeight> edt_storage;
  LandmarkMapStorage<32> landmark_storage;
  Route route{
      {{5.5f, 7.3f}, {14.5f, 7.3f}, {14.5f, 10.2f}, {10.0f, 10.5f}, {9.0f, 11.5f}, {6.8f, 11.5f}, {5.5f, 10.0f}}};

  OccupancyGrid grid() const { return grid_storage.grid(); }
  DistanceTransform edt() const { return edt_storage.view(); }
  LandmarkMap landmarks() const { return landmark_storage.view(); }
};

// The one office world of the process (built on first use; ~0.4 MB, never freed).
const OfficeWorld& office_world();

}  // namespace est::sim
