#pragma once
// Ray casting by table lookup over discretized headings (the "giant lookup table" of RangeLibc: Walsh and Karaman,
// "CDDT: Fast approximate 2D ray casting for accelerated localization", 2018, sec. II): for every cell and each of
// T headings 2 pi b / T, the range from the cell centre to the first occupied cell, cast once by an exact caster
// (GridRayCaster, or DistanceTransformRayCaster which gives the same ranges) and stored as uint16 in 1/16 cell.
//
// A query from (x, y) at heading a reads the two bins around a in the query point's cell (adjacent in memory):
//  - where the two ranges agree (|r0 - r1| <= 2 cells + r/8: one surface seen by both) they are interpolated
//    linearly in angle, else (an edge between them) the nearer bin is taken;
//  - the offset of (x, y) from the cell centre along the beam is subtracted (exact for a wall hit on the same
//    surface; the offset across the beam is not corrected).
// Conventions are GridRayCaster's: a start in an occupied cell, outside the map or non-finite returns 0; no hit
// within range returns max_range. A query's max_range above the table's build range is capped at the build range.
//
// Error against the exact caster (not exact: heading and position are quantized; the error is largest at edges,
// where a ray passing near a corner sees the other side of it, so the max error is not bounded below the range).
// Measured from random free cells in random directions, 20 000 rays to 20 m (tests/test_heading_range_table.cpp
// and bench_mcl print it):
//  - synthetic office 400 x 300 at 0.05 m, T = 64: mean |error| 0.156 m, median 0.007 m, p90 0.17 m, 86.8 % of
//    rays within 0.10 m, max 16.3 m;
//  - Intel map 888 x 848 at 0.05 m: T = 32: mean 0.75 m, median 0.035 m, p90 1.6 m, 65 % within 0.10 m;
//    T = 64: mean 0.55 m, median 0.019 m, p90 0.95 m, 76 %; T = 128: mean 0.39 m, median 0.012 m, p90 0.37 m,
//    84 %; T = 256: mean 0.32 m, median 0.009 m, p90 0.16 m, 88 %; max ~ the range at every T.
// Memory: 2 T bytes per cell (Intel 888 x 848: T = 32 46 MiB, 64 92 MiB, 128 184 MiB, 256 368 MiB): a host or
// large-RAM structure; on a board, a small map only (office 400 x 300 at T = 32: 7.3 MiB), else
// DistanceTransformRayCaster. Build: W H T casts from cell centres; with the distance-transform caster on the host
// (x86-64, -O3) the Intel map takes 2.5 s (T = 32), 4.9 s (64), 9.2 s (128), 17 s (256), the office at T = 64
// 0.6 s: done on the host and flashed, or at start-up on a fast target. Lookup: one cell row of T entries per
// particle, so the beam model reads it from cache (bench_mcl: the table path's ray costs a few ns inside the
// beam model; ~60 ns through cast() from random cells, mostly the atan2 and a cache miss).
#include <cstdint>

#include "est/map/occupancy_grid.hpp"
#include "est/math/fmath.hpp"

namespace est {

inline constexpr std::uint16_t kHeadingRangeNoHit = 65535;
inline constexpr std::int32_t kHeadingRangeUnitsPerCell = 16;

// Read-only view: T ranges per cell, cell-major (cell (cx, cy) at [(cy W + cx) T, ... + T)).
class HeadingRangeTable {
 public:
  HeadingRangeTable() = default;
  HeadingRangeTable(const std::uint16_t* units, const OccupancyGrid& grid, std::int32_t bins, float range_max)
      : units_(units),
        w_(grid.width()),
        h_(grid.height()),
        bins_(bins),
        mask_(static_cast<std::uint32_t>(bins - 1)),
        shift_(log2_of(bins)),
        ox_(grid.origin_x()),
        oy_(grid.origin_y()),
        res_(grid.resolution()),
        inv_res_(grid.inv_resolution()),
        bins_per_rad_(static_cast<float>(bins) / kTwoPi),
        range_max_(range_max) {}

  bool valid() const { return units_ != nullptr && w_ > 0 && h_ > 0 && bins_ > 0; }
  std::int32_t width() const { return w_; }
  std::int32_t height() const { return h_; }
  std::int32_t bins() const { return bins_; }
  float bins_per_rad() const { return bins_per_rad_; }
  float range_max() const { return range_max_; }
  const std::uint16_t* data() const { return units_; }
  // Raw entry: range from the centre of cell (cx, cy) at heading 2 pi b / T, in 1/16 cell, or kHeadingRangeNoHit.
  std::uint16_t units(std::int32_t cx, std::int32_t cy, std::int32_t b) const {
    return units_[(static_cast<std::uint32_t>(cy * w_ + cx) << shift_) + static_cast<std::uint32_t>(b)];
  }

  // The caster interface of GridRayCaster: (dx, dy) a unit vector. One atan2 per call; the beam model's table path
  // (beam_range_finder_model_table.hpp) gets the heading without it.
  float cast(float x, float y, float dx, float dy, float max_range) const {
    if (!fmath::isfinite(dx) || !fmath::isfinite(dy)) return 0.0f;
    return cast_bins(x, y, dx, dy, fmath::atan2(dy, dx) * bins_per_rad_, max_range);
  }

  // heading_bins: the ray's heading in bins (heading * bins_per_rad()), within [-2 T, 2 T]; (dx, dy) its unit vector.
  float cast_bins(float x, float y, float dx, float dy, float heading_bins, float max_range) const {
    return cast_from(origin(x, y), dx, dy, heading_bins, max_range);
  }

  // A start shared by many rays (the beam model's sensor position): its cell and its row of the table, found once;
  // row is null outside the map.
  struct Origin {
    float gx = 0.0f, gy = 0.0f;
    std::int32_t ix = 0, iy = 0;
    const std::uint16_t* row = nullptr;
  };
  Origin origin(float x, float y) const {
    Origin o;
    o.gx = (x - ox_) * inv_res_;
    o.gy = (y - oy_) * inv_res_;
    if (!(o.gx >= 0.0f && o.gy >= 0.0f && o.gx < static_cast<float>(w_) && o.gy < static_cast<float>(h_))) return o;
    o.ix = static_cast<std::int32_t>(o.gx);
    o.iy = static_cast<std::int32_t>(o.gy);
    if (o.ix >= w_) o.ix = w_ - 1;
    if (o.iy >= h_) o.iy = h_ - 1;
    o.row = units_ + (static_cast<std::uint32_t>(o.iy * w_ + o.ix) << shift_);
    return o;
  }

  // cast_bins() from a prepared origin: the same float.
  float cast_from(const Origin& o, float dx, float dy, float heading_bins, float max_range) const {
    if (o.row == nullptr) return 0.0f;
    if (!(max_range > 0.0f)) return 0.0f;
    const float f = heading_bins + static_cast<float>(2 * bins_);
    if (!(f >= 0.0f && f < static_cast<float>(4 * bins_))) return 0.0f;  // also rejects NaN
    const float gx = o.gx, gy = o.gy;
    const std::int32_t ix = o.ix, iy = o.iy;
    const std::uint16_t* row = o.row;
    const std::int32_t i0 = static_cast<std::int32_t>(f);
    const float frac = f - static_cast<float>(i0);
    const std::int32_t a = row[static_cast<std::uint32_t>(i0) & mask_];
    const std::int32_t b = row[static_cast<std::uint32_t>(i0 + 1) & mask_];
    if (a == 0 && b == 0) return 0.0f;  // occupied start cell (or a wall touching the centre)
    const float cap = max_range < range_max_ ? max_range : range_max_;
    float u = 0.0f;  // range from the cell centre, 1/16 cell
    const std::int32_t lo = a < b ? a : b;
    const std::int32_t gap = a < b ? b - a : a - b;
    if (b != kHeadingRangeNoHit && a != kHeadingRangeNoHit && gap <= 2 * kHeadingRangeUnitsPerCell + (lo >> 3)) {
      u = static_cast<float>(a) + frac * static_cast<float>(b - a);
    } else {
      const std::int32_t nearest = frac < 0.5f ? a : b;
      if (nearest == kHeadingRangeNoHit) return cap;
      u = static_cast<float>(nearest);
    }
    const float along = (gx - (static_cast<float>(ix) + 0.5f)) * dx + (gy - (static_cast<float>(iy) + 0.5f)) * dy;
    float r = (u * (1.0f / static_cast<float>(kHeadingRangeUnitsPerCell)) - along) * res_;
    if (!(r > 0.0f)) r = 0.0f;
    return r < cap ? r : cap;
  }

 private:
  static std::uint32_t log2_of(std::int32_t bins) {
    std::uint32_t s = 0;
    while ((1 << s) < bins && s < 16u) ++s;  // bins is a power of two <= 4096
    return s;
  }
  const std::uint16_t* units_ = nullptr;
  std::int32_t w_ = 0, h_ = 0, bins_ = 0;
  std::uint32_t mask_ = 0, shift_ = 0;
  float ox_ = 0.0f, oy_ = 0.0f, res_ = 1.0f, inv_res_ = 1.0f, bins_per_rad_ = 0.0f, range_max_ = 0.0f;
};

enum class HeadingRangeTableStatus : std::uint8_t {
  ok = 0,
  bad_grid,    // the grid is empty or invalid
  too_large,   // W H T entries exceed the buffer's capacity
  bad_bins,    // T is not a power of two in [4, 4096]
  bad_range,   // max range not finite, <= 0, or >= 4095 cells (the uint16 range in 1/16 cell)
};

// Runtime-capacity interface over caller-owned storage of `capacity` uint16 entries.
class HeadingRangeTableBuffer {
 public:
  HeadingRangeTableBuffer(const HeadingRangeTableBuffer&) = delete;
  HeadingRangeTableBuffer& operator=(const HeadingRangeTableBuffer&) = delete;

  std::uint32_t capacity() const { return capacity_; }

  // Casts W H T rays from the cell centres with `exact` (built on `grid`), max range `range_max`. Bounded: W H T
  // casts, each bounded by the caster. Nothing changes unless the result is ok.
  template <class Caster>
  HeadingRangeTableStatus build(const OccupancyGrid& grid, const Caster& exact, std::int32_t bins, float range_max) {
    if (!grid.valid()) return HeadingRangeTableStatus::bad_grid;
    if (bins < 4 || bins > 4096 || (bins & (bins - 1)) != 0) return HeadingRangeTableStatus::bad_bins;
    const std::uint64_t entries = static_cast<std::uint64_t>(grid.width()) *
                                  static_cast<std::uint64_t>(grid.height()) * static_cast<std::uint64_t>(bins);
    if (entries > capacity_) return HeadingRangeTableStatus::too_large;
    if (!fmath::isfinite(range_max) || !(range_max > 0.0f) || !(range_max * grid.inv_resolution() < 4095.0f))
      return HeadingRangeTableStatus::bad_range;
    const std::int32_t w = grid.width(), h = grid.height();
    const std::uint32_t ub = static_cast<std::uint32_t>(bins);
    const float units_per_m = grid.inv_resolution() * static_cast<float>(kHeadingRangeUnitsPerCell);
    view_ = HeadingRangeTable{};
    for (std::int32_t b = 0; b < bins; ++b) {
      float s = 0.0f, c = 0.0f;
      fmath::sincos(kTwoPi * static_cast<float>(b) / static_cast<float>(bins), s, c);
      for (std::int32_t cy = 0; cy < h; ++cy) {
        const float y = grid.cell_center_y(cy);
        for (std::int32_t cx = 0; cx < w; ++cx) {
          std::uint16_t v = 0;
          if (!grid.is_occupied(cx, cy)) {
            const float r = exact.cast(grid.cell_center_x(cx), y, c, s, range_max);
            v = r < range_max ? static_cast<std::uint16_t>(r * units_per_m + 0.5f) : kHeadingRangeNoHit;
          }
          units_[static_cast<std::uint32_t>(cy * w + cx) * ub + static_cast<std::uint32_t>(b)] = v;
        }
      }
    }
    view_ = HeadingRangeTable(units_, grid, bins, range_max);
    return HeadingRangeTableStatus::ok;
  }
  HeadingRangeTable view() const { return view_; }

 protected:
  HeadingRangeTableBuffer(std::uint16_t* units, std::uint32_t capacity) : units_(units), capacity_(capacity) {}
  ~HeadingRangeTableBuffer() = default;

 private:
  std::uint16_t* units_;
  std::uint32_t capacity_;
  HeadingRangeTable view_{};
};

// The owner: 2 WMax HMax TMax bytes, meant to be a static object.
template <std::int32_t WMax, std::int32_t HMax, std::int32_t TMax>
class HeadingRangeTableStorage final : public HeadingRangeTableBuffer {
  static_assert(WMax > 0 && HMax > 0 && TMax >= 4 && TMax <= 4096 && (TMax & (TMax - 1)) == 0,
                "T must be a power of two in [4, 4096]");
  static constexpr std::uint64_t kEntries64 =
      static_cast<std::uint64_t>(WMax) * static_cast<std::uint64_t>(HMax) * static_cast<std::uint64_t>(TMax);
  static_assert(kEntries64 < (1ull << 31), "at most 2^31 entries (4 GiB)");

 public:
  static constexpr std::uint32_t kEntries = static_cast<std::uint32_t>(kEntries64);
  static constexpr std::uint64_t kBytes = 2ull * kEntries64;
  HeadingRangeTableStorage() : HeadingRangeTableBuffer(units_, kEntries) {}

 private:
  std::uint16_t units_[kEntries];
};

}  // namespace est
