#pragma once
// Ray casting in an occupancy grid for the beam model's expected range z* (Thrun table 6.1, line 3).
//
// Both casters answer the same question: the distance along a ray from (x, y) in direction (dx, dy) (a unit
// vector) to the boundary of the first occupied cell it enters, capped at max_range. Conventions:
//  - unknown cells are free space; a ray that leaves the map returns max_range (no return);
//  - a start inside an occupied cell returns 0; a start outside the map or non-finite returns 0 as well (a particle
//    off the map explains no beam); max_range <= 0 or NaN returns 0;
//  - every loop is bounded by the map: at most W + H + 4 iterations (exact) or 2 (W + H) + 8 (accelerated).
//
// GridRayCaster: exact grid traversal (Amanatides and Woo, "A fast voxel traversal algorithm", 1987), one cell
// per step. Crossing parameters are recomputed from the cell index at every step, not accumulated, so both
// casters compute bit-identical boundary crossings.
//
// DistanceTransformRayCaster: sphere tracing on the exact Euclidean distance transform, finished with the same
// exact traversal. In a cell whose centre is D cells from the nearest occupied cell centre, no occupied cell is
// closer than D - sqrt(2) cells to any point of the cell, so the ray jumps D - sqrt(2) cells at once (rounded down
// to 1/16 cell); where that is less than one cell it steps cell by cell exactly like GridRayCaster. The result is
// the exact one, not an approximation, except for float rounding where a jump lands within ~1e-6 cell of a cell
// corner. Measured against GridRayCaster (tests/test_ray_casting.cpp prints it; tests/bench/bench_sensor_models):
//  - range error: synthetic office (20 000 rays to 30 m, 5 000 to 2 m) and Intel map (20 000 rays to 30 m) from
//    random free cells in random directions: 0 rays differ, max |error| 0 m (bit-identical);
//  - memory: the distance transform, 2 bytes per cell (Intel 888 x 848: 1.44 MiB), shared with the likelihood field;
//  - build: ~19 ms on the host for the Intel map (x86-64 2.6 GHz, -O3; distance_transform.hpp);
//  - speed, host, Intel map, rays from free cells >= 0.3 m from walls: exact 210-240 ns per ray, accelerated
//    155-190 ns (5 to 30 m max range); the cluttered Intel map gains ~1.3x, open rooms more (office: ~1.7x).
#include <cstdint>

#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"

namespace est {
namespace detail {

// A ray in cell units with the traversal state of Amanatides-Woo.
struct GridRay {
  float gx, gy;          // start, cells
  float dx, dy;          // direction (unit, so t is in cells along the ray)
  float inv_dx, inv_dy;  // only used when the matching step is non-zero
  std::int32_t step_x, step_y;
  std::int32_t ahead_x, ahead_y;  // 1 when stepping up: the boundary crossed next is ix + 1
  std::int32_t ix, iy;
  float t_max;  // max_range in cells

  // False when the start is outside the map or anything is non-finite.
  bool init(const OccupancyGrid& g, float x, float y, float ddx, float ddy, float max_range) {
    return start(g, x, y) && aim(g, ddx, ddy, max_range);
  }
  // The two halves of init(), for many rays from one start: start() once, then aim() per ray (either order).
  // start: false when (x, y) is outside the map or not finite.
  bool start(const OccupancyGrid& g, float x, float y) {
    gx = (x - g.origin_x()) * g.inv_resolution();
    gy = (y - g.origin_y()) * g.inv_resolution();
    if (!(gx >= 0.0f && gy >= 0.0f && gx < static_cast<float>(g.width()) && gy < static_cast<float>(g.height())))
      return false;
    ix = static_cast<std::int32_t>(gx);
    iy = static_cast<std::int32_t>(gy);
    if (ix >= g.width()) ix = g.width() - 1;
    if (iy >= g.height()) iy = g.height() - 1;
    return true;
  }
  // aim: false when max_range is not positive or the direction not finite.
  bool aim(const OccupancyGrid& g, float ddx, float ddy, float max_range) {
    if (!(max_range > 0.0f) || !fmath::isfinite(ddx) || !fmath::isfinite(ddy)) return false;
    aim_checked(g, ddx, ddy, max_range);
    return true;
  }
  // aim() of a finite direction and a positive max_range, which the caller has checked.
  void aim_checked(const OccupancyGrid& g, float ddx, float ddy, float max_range) {
    constexpr float kTiny = 1e-9f;
    dx = ddx;
    dy = ddy;
    step_x = ddx > kTiny ? 1 : (ddx < -kTiny ? -1 : 0);
    step_y = ddy > kTiny ? 1 : (ddy < -kTiny ? -1 : 0);
    ahead_x = step_x > 0 ? 1 : 0;
    ahead_y = step_y > 0 ? 1 : 0;
    inv_dx = step_x != 0 ? 1.0f / ddx : 0.0f;
    inv_dy = step_y != 0 ? 1.0f / ddy : 0.0f;
    t_max = max_range * g.inv_resolution();
  }
  static constexpr float kNever = 3.0e38f;
  float t_x() const { return step_x != 0 ? (static_cast<float>(ix + ahead_x) - gx) * inv_dx : kNever; }
  float t_y() const { return step_y != 0 ? (static_cast<float>(iy + ahead_y) - gy) * inv_dy : kNever; }
  // The parameter (cells) at which the ray leaves the map of w x h cells: the same float as step()'s crossing of the
  // map's edge (t_x() at ix + ahead_x = w, or 0 stepping down), so a step leaves the map exactly when its t reaches
  // it; kNever along an axis the ray does not step on.
  float t_exit(std::int32_t w, std::int32_t h) const {
    const float ex = step_x != 0 ? (static_cast<float>(ahead_x * w) - gx) * inv_dx : kNever;
    const float ey = step_y != 0 ? (static_cast<float>(ahead_y * h) - gy) * inv_dy : kNever;
    return ex < ey ? ex : ey;
  }
  // Moves to the cell the ray is in at parameter t (cells), after a jump, for a t below t_exit(): the point is on the
  // map but for rounding at its edge (a few 2^-24 of the map's size, so above -1 cell; on an axis the ray does not
  // step on, |t d| <= 1e-9 t stays under a cell for the t a bounded walk reaches), which truncation towards zero and
  // the clamps to the last cell take.
  void land_inside(float t, std::int32_t w, std::int32_t h) {
    ix = static_cast<std::int32_t>(gx + t * dx);
    iy = static_cast<std::int32_t>(gy + t * dy);
    if (ix >= w) ix = w - 1;
    if (iy >= h) iy = h - 1;
  }
  // Moves into the next cell along the ray; returns the ray parameter (cells) at which it was entered.
  float step() {
    const float tx = t_x();
    const float ty = t_y();
    if (tx < ty) {
      ix += step_x;
      return tx;
    }
    iy += step_y;
    return ty;
  }
};

inline float cells_to_range(float t_cells, float resolution, float max_range) {
  const float r = t_cells * resolution;
  return r < max_range ? r : max_range;
}

}  // namespace detail

class GridRayCaster {
 public:
  explicit GridRayCaster(const OccupancyGrid& grid) : grid_(grid) {}
  const OccupancyGrid& grid() const { return grid_; }

  float cast(float x, float y, float dx, float dy, float max_range) const {
    detail::GridRay r;
    if (!r.init(grid_, x, y, dx, dy, max_range)) return 0.0f;
    if (grid_.is_occupied_value(grid_.at(r.ix, r.iy))) return 0.0f;
    const std::int32_t bound = grid_.width() + grid_.height() + 4;
    for (std::int32_t n = 0; n < bound; ++n) {
      const float t = r.step();
      if (!(t < r.t_max) || !grid_.contains(r.ix, r.iy)) return max_range;
      if (grid_.is_occupied_value(grid_.at(r.ix, r.iy))) return detail::cells_to_range(t, grid_.resolution(), max_range);
    }
    return max_range;
  }

 private:
  OccupancyGrid grid_;
};

class DistanceTransformRayCaster {
 public:
  // The transform must have been built from `grid` (same size); checked by valid().
  DistanceTransformRayCaster(const OccupancyGrid& grid, const DistanceTransform& edt) : grid_(grid), edt_(edt) {}
  bool valid() const {
    return grid_.valid() && edt_.valid() && edt_.width() == grid_.width() && edt_.height() == grid_.height();
  }
  const OccupancyGrid& grid() const { return grid_; }
  const DistanceTransform& distance_transform() const { return edt_; }

  // A jump needs a centre distance of at least sqrt(2) + 1 cells; 23 = ceil(16 sqrt(2)).
  static constexpr std::int32_t kMarginUnits = 23;
  static constexpr std::int32_t kMinJumpUnits = kMarginUnits + 16;

  float cast(float x, float y, float dx, float dy, float max_range) const {
    detail::GridRay r;
    if (!r.init(grid_, x, y, dx, dy, max_range)) return 0.0f;
    const std::uint16_t* q = edt_.data();
    const std::int32_t w = grid_.width(), h = grid_.height();
    std::int32_t units = q[r.iy * w + r.ix];
    if (units == 0) return 0.0f;
    float t = 0.0f;
    const std::int32_t bound = 2 * (w + h) + 8;
    // The walk ends at max_range or where the ray leaves the map (t_exit(): a step has left it exactly when its t
    // reaches it), so neither move checks its cell against the map.
    const float t_exit = r.t_exit(w, h), t_end = r.t_max < t_exit ? r.t_max : t_exit;
    for (std::int32_t n = bound; n > 0; --n) {  // counted down: one compare fewer a move on the boards
      if (units >= kMinJumpUnits) {
        t += static_cast<float>(units - kMarginUnits) * (1.0f / 16.0f);
        if (!(t < t_end)) return max_range;
        r.land_inside(t, w, h);
      } else {
        t = r.step();
        if (!(t < t_end)) return max_range;
      }
      units = q[r.iy * w + r.ix];
      if (units == 0) return detail::cells_to_range(t, grid_.resolution(), max_range);
    }
    return max_range;
  }

 private:
  OccupancyGrid grid_;
  DistanceTransform edt_;
};

}  // namespace est
