#pragma once
// Occupancy grid mapping with known poses, Probabilistic Robotics table 9.1 (occupancy_grid_mapping), with the
// inverse range sensor model of table 9.2 (inverse_range_sensor_model): per scan, every cell a beam crosses before
// its end point gets l_free, the cell of the end point gets l_occ (alpha = one cell), cells beyond the end point get
// nothing (l_0). A max-range reading (z >= the scan's range_max, no return) frees the cells up to free_range_max
// and marks nothing; a hit beyond hit_range_max is treated the same (far readings of a real laser are unreliable).
// The log odds are clamped to [l_min, l_max], so the map can change its mind about a door.
//
// Differences from the book, on purpose: table 9.1 visits every cell in the perceptual field once per scan with the
// beam nearest in bearing; here each beam updates the cells its ray crosses (the usual ray-casting form), so a cell
// near the robot crossed by several beams of one scan is freed by each. The traversal is est/map/ray_casting.hpp's
// exact grid traversal (Amanatides-Woo), bounded by W + H + 4 steps per beam.
//
// The log odds live in a caller-owned buffer of W x H floats (LogOddsGrid is a view: no heap, the capacity is the
// caller's); to_occupancy() turns them into the map's uint8 cells (percent, kUnknownCell where no beam passed).
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/fmath.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

struct InverseRangeSensorParams {
  float l_occ = 0.85f;    // log odds of p = 0.7
  float l_free = -0.4f;   // log odds of p = 0.4
  float l_min = -8.0f;
  float l_max = 8.0f;
  float hit_range_max = 30.0f;   // m: hits beyond are not mapped as obstacles
  float free_range_max = 30.0f;  // m: free space is marked up to here at most
};

struct MappingCounters {
  std::uint32_t scans = 0;
  std::uint32_t beams_hit = 0;      // end point marked occupied
  std::uint32_t beams_free = 0;     // max-range or beyond hit_range_max: free space only
  std::uint32_t beams_skipped = 0;  // unusable reading, or the sensor off the map
  std::uint32_t cells_updated = 0;
};

class LogOddsGrid {
 public:
  // `cells` holds width * height floats, owned by the caller and outliving the view; reset() zeroes them (l_0 = 0).
  LogOddsGrid(float* cells, std::int32_t width, std::int32_t height, float resolution, float origin_x, float origin_y)
      : cells_(cells), geometry_(nullptr, width, height, resolution, origin_x, origin_y) {}

  bool valid() const {
    return cells_ != nullptr && geometry_.width() > 0 && geometry_.height() > 0 &&
           fmath::isfinite(geometry_.resolution()) &&
           geometry_.resolution() > 0.0f;
  }
  std::int32_t width() const { return geometry_.width(); }
  std::int32_t height() const { return geometry_.height(); }
  const OccupancyGrid& geometry() const { return geometry_; }
  float at(std::int32_t cx, std::int32_t cy) const { return cells_[geometry_.index(cx, cy)]; }

  void reset() {
    const std::int32_t n = geometry_.cell_count();
    for (std::int32_t i = 0; i < n; ++i) cells_[i] = 0.0f;
  }

  // Table 9.1, lines 2-4, for one scan taken at `robot` by a sensor at `mount` on the robot.
  void update(const Pose2& robot, const Pose2& mount, const ScanLayout& layout, const float* ranges,
              const InverseRangeSensorParams& p, MappingCounters& counters) {
    if (!valid() || ranges == nullptr || layout.count <= 0 || !robot.is_finite()) return;
    ++counters.scans;
    const SensorFrame f = sensor_frame(robot, mount);
    for (std::int32_t k = 0; k < layout.count; ++k) {
      const float z = ranges[k];
      if (!(z >= layout.range_min) || z != z) {
        ++counters.beams_skipped;
        continue;
      }
      const bool hit = z < layout.range_max && z <= p.hit_range_max;
      float length = hit ? z : p.free_range_max;
      if (!hit && z < length) length = z;
      const float a = layout.angle_min + static_cast<float>(k) * layout.angle_increment;
      float s = 0.0f, c = 0.0f;
      fmath::sincos(a, s, c);
      const float dx = f.c * c - f.s * s, dy = f.s * c + f.c * s;
      if (!trace(f.x, f.y, dx, dy, length, hit, p, counters)) {
        ++counters.beams_skipped;
        continue;
      }
      ++(hit ? counters.beams_hit : counters.beams_free);
    }
  }

  // Cell value in percent from the log odds (p = 1 - 1 / (1 + e^l)), kUnknownCell where l = l_0 exactly.
  static std::uint8_t to_cell(float l) {
    if (l == 0.0f) return kUnknownCell;
    const float pr = 1.0f - 1.0f / (1.0f + fmath::exp(l));
    const float pct = pr * 100.0f + 0.5f;
    return static_cast<std::uint8_t>(pct < 0.0f ? 0.0f : (pct > 100.0f ? 100.0f : pct));
  }
  // The whole grid into `out` (same size and geometry); false when it does not fit.
  bool to_occupancy(OccupancyGridBuffer& out) const {
    if (!valid() || out.configure(width(), height(), geometry_.resolution(), geometry_.origin_x(),
                                  geometry_.origin_y()) != MapStatus::ok)
      return false;
    for (std::int32_t cy = 0; cy < height(); ++cy)
      for (std::int32_t cx = 0; cx < width(); ++cx) out.set(cx, cy, to_cell(at(cx, cy)));
    return true;
  }

 private:
  void add(std::int32_t cx, std::int32_t cy, float l, const InverseRangeSensorParams& p, MappingCounters& counters) {
    float& v = cells_[geometry_.index(cx, cy)];
    float n = v + l;  // table 9.1 line 4 with l_0 = 0
    if (n < p.l_min) n = p.l_min;
    if (n > p.l_max) n = p.l_max;
    if (n == 0.0f) n = l > 0.0f ? 1e-6f : -1e-6f;  // seen: never back to "unknown"
    v = n;
    ++counters.cells_updated;
  }

  // Frees the cells from the sensor to `length` along (dx, dy), then marks the end point's cell when `hit`.
  bool trace(float x, float y, float dx, float dy, float length, bool hit, const InverseRangeSensorParams& p,
             MappingCounters& counters) {
    detail::GridRay r;
    if (!r.init(geometry_, x, y, dx, dy, length > 0.0f ? length : geometry_.resolution())) return false;
    const float t_end = length * geometry_.inv_resolution();
    const std::int32_t bound = geometry_.width() + geometry_.height() + 4;
    for (std::int32_t n = 0; n < bound; ++n) {
      const std::int32_t cx = r.ix, cy = r.iy;
      const float t_next = r.step();
      if (!(t_next < t_end)) {  // the end point lies in cell (cx, cy)
        add(cx, cy, hit ? p.l_occ : p.l_free, p, counters);
        return true;
      }
      add(cx, cy, p.l_free, p, counters);
      if (!geometry_.contains(r.ix, r.iy)) return true;  // the ray leaves the map
    }
    return true;
  }

  float* cells_;
  OccupancyGrid geometry_;  // geometry only (no cells)
};

}  // namespace est
