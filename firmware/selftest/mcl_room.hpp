#pragma once
// The room the MCL sections localize in: 6.4 m x 4.8 m at 0.1 m, walls round it and what each section furnishes it
// with, its distance transform, the likelihood field (z_hit 0.85, z_rand 0.10, range 6 m) with its per-cell grid,
// the distance-transform ray caster and the free space 0.2 m clear of obstacles. One static storage for every
// section, rebuilt by each call of mcl_room(), so each section starts afresh.
#include <cstdint>

#include "est/filter/free_space_sampler.hpp"
#include "est/filter/particle_set.hpp"
#include "est/geometry/pose2.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/util/trace.hpp"

namespace est::selftest {

using MclRoomGrid = OccupancyGridStorage<64, 48>;

struct MclRoom {
  OccupancyGrid grid;
  const LikelihoodField& field;
  LikelihoodFieldGrid field_grid;
  DistanceTransformRayCaster caster;
  FreeSpaceSampler free_space;
  bool is_free(float x, float y) const {
    std::int32_t cx = 0, cy = 0;
    return grid.world_to_cell(x, y, cx, cy) && grid.classify(cx, cy) == CellClass::free;
  }
};

// The walls, then `furnish` draws the section's obstacles.
MclRoom mcl_room(void (*furnish)(MclRoomGrid&));

// 60 beams over the full circle, 0.05-6 m, and the ranges seen from `truth` with U(-0.02, 0.02) m noise.
inline constexpr std::int32_t kMclRoomBeams = 60;
ScanLayout mcl_room_scan_layout();
void mcl_room_scan(const MclRoom& room, const Pose2& truth, Rng& world, float (&ranges)[kMclRoomBeams]);

// The bicycle the sections drive and predict with (frame 0.5 m, its noise).
BicycleParams mcl_room_bicycle();

// Every particle of the set: pose and log weight.
void add_particles(Trace& d, ConstParticleSetView p);

}  // namespace est::selftest
