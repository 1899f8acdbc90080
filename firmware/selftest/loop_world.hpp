#pragma once
// The small world the loop sections drive their robots through: the 5 m x 4 m map (walls, an L-shaped partition
// and a box, so a scan constrains every direction) with what MCL needs of it, the six landmarks the EKF sections
// sight, and the sensors: a 60-beam scan ray cast from the true pose, and range / bearing / signature sightings.
// Everything lives in static storage (the map and its transform are ~20 KiB) and is rebuilt by every call of
// small_map(), so each section starts afresh.
#include <cstdint>

#include "est/filter/free_space_sampler.hpp"
#include "est/loop/inputs.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::selftest {

inline constexpr loop::TimeNs kMs = 1000000;

struct SmallMap {
  OccupancyGrid grid;
  const LikelihoodField& field;  // range_max 6 m, distances capped at 1 m
  FreeSpaceSampler free_space;   // 0.15 m clear of obstacles
  GridRayCaster caster;
};
// (Re)builds the map at 0.1 m, origin (0, 0).
SmallMap small_map();

// 60 beams over the full circle, 0.05-6 m.
inline constexpr std::int32_t kSmallScanBeams = 60;
ScanLayout small_scan_layout();
// The ranges seen from `truth`, with N(0, 0.02 m) noise.
void simulate_small_scan(const GridRayCaster& caster, const Pose2& truth, Rng& world, float (&ranges)[kSmallScanBeams]);

// Six landmarks round the map (signatures 1-6).
inline constexpr std::int32_t kSmallLandmarkCount = 6;
extern const Landmark kSmallLandmarks[kSmallLandmarkCount];
// Every landmark seen from `truth` at t: range, bearing and signature with N(0, 0.05 m), N(0, 0.02 rad) and
// N(0, 0.1) noise; the correspondence given (id) when `known`, else -1 (maximum likelihood).
void sight_small_landmarks(const Pose2& truth, loop::TimeNs t, bool known, Rng& world,
                           loop::LandmarkInput (&out)[kSmallLandmarkCount]);

}  // namespace est::selftest
