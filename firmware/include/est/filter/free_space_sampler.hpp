#pragma once
// Poses drawn uniformly over the free space of an occupancy grid: the initial belief of global localization and the
// source of augmented MCL's random particles (Thrun table 8.3, line 14: "add random pose"). A uniform position in
// the map's bounding box is kept when its cell is free and at least `clearance` from the nearest occupied cell
// (read from the distance transform: a robot's centre is never inside a wall); the heading is uniform on [-pi, pi).
// Rejection is bounded by max_tries: a draw that fails is reported (the filter counts it), never looped on.
// The probability of failure is (1 - free share)^max_tries: 0.2^24 ~ 2e-17 for an office that is 80 % free.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/math/fmath.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

class FreeSpaceSampler {
 public:
  FreeSpaceSampler() = default;
  // The transform must have been built from `grid`.
  FreeSpaceSampler(const OccupancyGrid& grid, const DistanceTransform& edt, float clearance,
                   std::uint32_t max_tries = 24u)
      : grid_(grid), edt_(edt), max_tries_(max_tries) {
    const float units = clearance > 0.0f ? clearance / edt.metres_per_unit() : 0.0f;
    min_units_ = units < 65535.0f ? static_cast<std::uint16_t>(units) : std::uint16_t{65535u};
    if (min_units_ == 0u) min_units_ = 1u;  // never inside an occupied cell
  }

  bool valid() const {
    return grid_.valid() && edt_.valid() && edt_.width() == grid_.width() && edt_.height() == grid_.height();
  }

  // The cell test of a draw: free (not unknown) and clear of obstacles.
  bool admissible(std::int32_t cx, std::int32_t cy) const {
    return grid_.classify(cx, cy) == CellClass::free && edt_.units(cx, cy) >= min_units_;
  }
  bool admissible_at(float x, float y) const {
    std::int32_t cx = 0, cy = 0;
    return grid_.world_to_cell(x, y, cx, cy) && admissible(cx, cy);
  }

  // Three uniforms per try. False after max_tries rejections (p is then untouched).
  bool operator()(Rng& rng, Pose2& p) const {
    if (!valid()) return false;
    const float w = static_cast<float>(grid_.width()) * grid_.resolution();
    const float h = static_cast<float>(grid_.height()) * grid_.resolution();
    for (std::uint32_t t = 0; t < max_tries_; ++t) {
      const float x = grid_.origin_x() + rng.uniform() * w;
      const float y = grid_.origin_y() + rng.uniform() * h;
      const float theta = rng.uniform(-kPi, kPi);
      if (admissible_at(x, y)) {
        p = {x, y, theta};
        return true;
      }
    }
    return false;
  }

 private:
  OccupancyGrid grid_{};
  DistanceTransform edt_{};
  std::uint16_t min_units_ = 1u;
  std::uint32_t max_tries_ = 24u;
};

}  // namespace est
