#pragma once
// Exact Euclidean distance transform of an occupancy grid (Felzenszwalb and Huttenlocher, "Distance transforms of
// sampled functions", 2012; the integer lower-envelope form of Meijster et al. 2000): for every cell, the distance
// from its centre to the centre of the nearest occupied cell. Shared by the likelihood field (Thrun table 6.3) and
// the accelerated ray caster.
//
// Stored as uint16 in 1/16 of a cell, rounded DOWN: q = floor(16 * d_cells), so q / 16 <= d < q / 16 + 1/16 and a
// step of q / 16 cells never overshoots an obstacle. q == 0 exactly on occupied cells. Distances of 4096 cells and
// more saturate at 65535; a grid with no occupied cell gives 65535 everywhere. Memory: 2 bytes per cell (Intel
// map, 888 x 848: 1.44 MiB) plus 12 bytes per cell of max(W, H) of scratch.
//
// Cost: two passes, O(W H), every loop bounded by W or H (the envelope's pops total at most W per row). Measured
// build time on the host (x86-64 2.6 GHz, -O3): ~19 ms for the 888 x 848 Intel map (tests/bench/bench_sensor_models);
// meant for start-up (or done on the host and flashed).
#include <cstdint>

#include "est/map/occupancy_grid.hpp"

namespace est {

inline constexpr std::uint16_t kDistanceUnitsPerCell = 16;
inline constexpr std::uint16_t kDistanceSaturated = 65535;

class DistanceTransform {
 public:
  DistanceTransform() = default;
  DistanceTransform(const std::uint16_t* q, std::int32_t width, std::int32_t height, float resolution)
      : q_(q), width_(width), height_(height), metres_per_unit_(resolution / 16.0f) {}

  bool valid() const { return q_ != nullptr && width_ > 0; }
  std::int32_t width() const { return width_; }
  std::int32_t height() const { return height_; }
  const std::uint16_t* data() const { return q_; }
  // Distance in 1/16 cell, floored.
  std::uint16_t units(std::int32_t cx, std::int32_t cy) const { return q_[cy * width_ + cx]; }
  float metres_per_unit() const { return metres_per_unit_; }
  float metres(std::int32_t cx, std::int32_t cy) const { return static_cast<float>(units(cx, cy)) * metres_per_unit_; }

 private:
  const std::uint16_t* q_ = nullptr;
  std::int32_t width_ = 0;
  std::int32_t height_ = 0;
  float metres_per_unit_ = 0.0f;
};

// Runtime-capacity interface: build() fills it from a grid of at most capacity_width x capacity_height cells.
class DistanceTransformBuffer {
 public:
  DistanceTransformBuffer(const DistanceTransformBuffer&) = delete;
  DistanceTransformBuffer& operator=(const DistanceTransformBuffer&) = delete;

  // Exact EDT of `grid`'s occupied cells (CellClass::occupied); unknown and free cells are both free space.
  MapStatus build(const OccupancyGrid& grid);
  DistanceTransform view() const { return DistanceTransform(q_, width_, height_, resolution_); }

 protected:
  DistanceTransformBuffer(std::uint16_t* q, std::int32_t* scratch_f, std::int32_t* scratch_s, std::int32_t* scratch_t,
                          std::int32_t cap_w, std::int32_t cap_h)
      : q_(q), f_(scratch_f), s_(scratch_s), t_(scratch_t), cap_w_(cap_w), cap_h_(cap_h) {}
  ~DistanceTransformBuffer() = default;

 private:
  std::uint16_t* q_;
  std::int32_t* f_;
  std::int32_t* s_;
  std::int32_t* t_;
  std::int32_t cap_w_;
  std::int32_t cap_h_;
  std::int32_t width_ = 0;
  std::int32_t height_ = 0;
  float resolution_ = 1.0f;
};

template <std::int32_t WMax, std::int32_t HMax>
class DistanceTransformStorage final : public DistanceTransformBuffer {
  static_assert(WMax > 0 && HMax > 0 && WMax <= 16384 && HMax <= 16384, "sides are limited to 16384 cells");
  static constexpr std::uint32_t kSide = static_cast<std::uint32_t>(WMax > HMax ? WMax : HMax);

 public:
  static constexpr std::uint32_t kBytes =
      2u * static_cast<std::uint32_t>(WMax) * static_cast<std::uint32_t>(HMax) + 12u * kSide;

  DistanceTransformStorage() : DistanceTransformBuffer(q_, f_, s_, t_, WMax, HMax) {}

 private:
  std::uint16_t q_[static_cast<std::uint32_t>(WMax) * static_cast<std::uint32_t>(HMax)];
  std::int32_t f_[kSide];
  std::int32_t s_[kSide];
  std::int32_t t_[kSide];
};

}  // namespace est
