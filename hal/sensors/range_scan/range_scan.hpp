#pragma once
// A 2D rangefinder scan: beam i points at angle_min + i * angle_increment in the sensor frame (counter-clockwise).
// Readings at or beyond range_max (including +inf, "no return") are max-range readings, which the beam model of
// Probabilistic Robotics (Table 6.1) scores with its p_max term; NaN, -inf and readings below range_min are unusable.
#include <cstddef>
#include <cstdint>

#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

struct ScanGeometry {
  float angle_min_rad = 0.0f;
  float angle_increment_rad = 0.0f;
  float range_min_m = 0.0f;
  float range_max_m = 0.0f;
  float scan_time_s = 0.0f;  // time between two scans (the sweep period)
};

// What code that does not care about the capacity sees (the ETL split: the capacity lives only in RangeScan<K>).
struct RangeScanView {
  TimeNs stamp_ns = 0;
  ScanGeometry geometry;
  const float* ranges = nullptr;
  std::size_t count = 0;
};

template <std::size_t K>
struct RangeScan {
  static_assert(K > 0, "a scan holds at least one beam");
  static constexpr std::size_t kCapacity = K;

  TimeNs stamp_ns = 0;
  ScanGeometry geometry;
  std::size_t count = 0;
  float ranges[K] = {};

  RangeScanView view() const { return {stamp_ns, geometry, ranges, count}; }
  // Copies a view of at most K beams; returns false (and copies nothing) when it does not fit.
  bool assign(const RangeScanView& v) {
    if (v.count > K || (v.count > 0 && v.ranges == nullptr)) return false;
    stamp_ns = v.stamp_ns;
    geometry = v.geometry;
    count = v.count;
    for (std::size_t i = 0; i < v.count; ++i) ranges[i] = v.ranges[i];
    return true;
  }
};

enum class BeamClass : unsigned char { hit, max_range, unusable };

inline BeamClass classify_beam(float range_m, const ScanGeometry& g) {
  if (range_m != range_m) return BeamClass::unusable;  // NaN
  if (range_m >= g.range_max_m) return BeamClass::max_range;
  if (range_m < g.range_min_m) return BeamClass::unusable;  // includes -inf
  return BeamClass::hit;
}

// The loop's input; the readings are not copied: valid while the view is (the loop's queue copies them).
template <typename Push>
void to_loop_inputs(const RangeScanView& s, Push&& push) {
  est::loop::ScanInput in;
  in.t_ns = s.stamp_ns;
  in.layout.angle_min = s.geometry.angle_min_rad;
  in.layout.angle_increment = s.geometry.angle_increment_rad;
  in.layout.count = s.count > 0x7fffffffu ? 0x7fffffff : static_cast<std::int32_t>(s.count);
  in.layout.range_min = s.geometry.range_min_m;
  in.layout.range_max = s.geometry.range_max_m;
  in.ranges = s.ranges;
  push(in);
}

}  // namespace hal
