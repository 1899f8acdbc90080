#pragma once
// The room the beam-model sections (beam_table, beam_cone) weigh scans in: 6.4 m x 4.8 m at 0.1 m, walls round it, a
// partition and a desk; and a scan of it from a pose, cast exactly with a little noise, one max and one short reading.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/fmath.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::selftest {

inline void furnish_beam_room(OccupancyGridStorage<64, 48>& room) {
  room.configure(64, 48, 0.1f, -0.5f, -0.3f, kFreeCell);
  room.fill_rect(0, 0, 63, 0, kOccupiedCell);
  room.fill_rect(0, 47, 63, 47, kOccupiedCell);
  room.fill_rect(0, 0, 0, 47, kOccupiedCell);
  room.fill_rect(63, 0, 63, 47, kOccupiedCell);
  room.fill_rect(40, 0, 40, 30, kOccupiedCell);
  room.fill_rect(10, 10, 18, 13, kOccupiedCell);
}

// K beams all round from `truth`, 6 m max range, +-3 cm of noise; beam 9 a max reading, beam 30 a short one.
template <std::int32_t K>
void beam_room_scan(const OccupancyGrid& grid, const Pose2& truth, Rng& rng, PreparedScan<K>& scan) {
  const GridRayCaster exact(grid);
  const ScanLayout layout{-kPi, kTwoPi / static_cast<float>(K), K, 0.02f, 6.0f};
  float ranges[static_cast<std::uint32_t>(K)];
  for (std::int32_t k = 0; k < K; ++k) {
    float s = 0.0f, c = 0.0f;
    fmath::sincos(truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment, s, c);
    ranges[k] = exact.cast(truth.x, truth.y, c, s, 6.0f) + rng.uniform(-0.03f, 0.03f);
  }
  ranges[9] = 7.0f;
  ranges[30] = 0.3f;
  scan.prepare(layout, ranges, 1);
}

// The beam model the sections weigh with: the default parameters at the scan's 6 m.
inline BeamRangeFinderModel beam_room_model() {
  BeamRangeFinderModel beam;
  BeamModelParams bp;
  bp.range_max = 6.0f;
  beam.configure(bp);
  return beam;
}

}  // namespace est::selftest
