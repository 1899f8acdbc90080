#pragma once
// Range scans synthesized from the true pose: the exact grid traversal gives z*, then each reading is, as in the
// beam model's own mixture (Thrun 6.3.1), z* + N(0, sigma^2) with probability 1 - p_rand - p_short, a uniform
// random reading with probability p_rand, a short reading (uniform on [0, z*), an unmapped obstacle) with p_short;
// anything at or beyond range_max reads range_max (no return).
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::sim {

struct RangeNoise {
  float sigma = 0.02f;  // m
  float p_rand = 0.01f;
  float p_short = 0.01f;
};

// `layout.count` readings into `ranges` (resized), for a sensor at robot (+) mount.
void simulate_scan(const OccupancyGrid& world, const Pose2& robot, const Pose2& mount, const ScanLayout& layout,
                   const RangeNoise& noise, Rng& rng, std::vector<float>& ranges);

// 360 beams at 1 deg, counter-clockwise from straight behind, 0.05 .. max_range m: the usual 2D lidar.
inline ScanLayout lidar_360(float max_range) {
  return {-3.14159265358979f, 6.28318530717958647692f / 360.0f, 360, 0.05f, max_range};
}

}  // namespace est::sim
