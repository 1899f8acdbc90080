#pragma once
// A range scan prepared once per measurement, then evaluated against N particles by the range finder models
// (Thrun ch. 6.3-6.4). Preparing validates every reading once (the verdict is the same for every particle),
// keeps every s-th beam, and stores each kept beam's unit vector in the sensor frame, so a particle costs one
// sincos and the beams only multiplications.
//
// Layout: beam k (0 <= k < count) has bearing angle_min + k * angle_increment in the sensor frame (x forward,
// y left, counter-clockwise positive), so 360 x 1 deg, 180 x 1 deg, 181 x 1 deg, 683 x 0.36 deg ... all fit.
// Readings: finite and >= range_min are used; >= range_max is a max-range reading (kept, flagged, clamped to
// range_max); +inf is "no return within range" (ROS REP 117) and so a max-range reading too, the same rule as
// the HAL's classify_beam; NaN and -inf are rejected as nonfinite; below
// range_min (including negative) rejected as below_min. Rejections are counted, never evaluated.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"

namespace est {

struct ScanLayout {
  float angle_min = 0.0f;        // rad, bearing of beam 0 in the sensor frame
  float angle_increment = 0.0f;  // rad
  std::int32_t count = 0;        // K, readings in the scan
  float range_min = 0.0f;        // m, readings below are invalid
  float range_max = 0.0f;        // m, the book's z_max
};

enum class ScanStatus : std::uint8_t {
  ok = 0,
  bad_layout,     // count <= 0, non-finite angles, range_max <= range_min or non-finite, stride < 1
  too_many_beams, // more kept beams than the prepared scan's capacity
  no_beams,       // every reading was rejected (the scan carries no information)
};

struct ScanCounters {
  std::int32_t kept = 0;               // beams the models evaluate (max-range readings included)
  std::int32_t max_readings = 0;       // of the kept, readings >= range_max
  std::int32_t rejected_nonfinite = 0; // NaN or -inf
  std::int32_t rejected_below_min = 0; // < range_min, negative included
  std::int32_t skipped_stride = 0;     // not on the subsampling grid
};

// Read-only view of the kept beams.
struct ScanBeams {
  const float* range = nullptr;        // m, clamped to range_max
  const float* ux = nullptr;           // unit vector of the beam in the sensor frame
  const float* uy = nullptr;
  const std::uint8_t* is_max = nullptr;  // 1 for a max-range reading
  std::int32_t count = 0;
  float range_max = 0.0f;
};

// The pose of the sensor in the world: x (+) mount, with the rotation kept as cos/sin.
struct SensorFrame {
  float x, y, c, s;
  float heading() const { return fmath::atan2(s, c); }
  // Beam k's direction in the world frame: its unit vector in the sensor frame, turned by the sensor's heading.
  void beam(const ScanBeams& z, std::int32_t k, float& dx, float& dy) const {
    dx = c * z.ux[k] - s * z.uy[k];
    dy = s * z.ux[k] + c * z.uy[k];
  }
};
inline SensorFrame sensor_frame(const Pose2& robot, const Pose2& mount) {
  float c = 0.0f, s = 0.0f;
  fmath::sincos(robot.theta, s, c);
  float cs = 0.0f, ss = 0.0f;
  fmath::sincos(robot.theta + mount.theta, ss, cs);
  return {robot.x + c * mount.x - s * mount.y, robot.y + s * mount.x + c * mount.y, cs, ss};
}

class PreparedScanBuffer {
 public:
  PreparedScanBuffer(const PreparedScanBuffer&) = delete;
  PreparedScanBuffer& operator=(const PreparedScanBuffer&) = delete;

  std::int32_t capacity() const { return capacity_; }

  // Keeps readings first, first + stride, ... (stride >= 1). K sincos calls. On any status but ok the prepared
  // scan is empty (count 0), so a model evaluated on it returns 0 for every particle: no update.
  ScanStatus prepare(const ScanLayout& layout, const float* ranges, std::int32_t stride = 1,
                     std::int32_t first = 0) {
    counters_ = ScanCounters{};
    count_ = 0;
    range_max_ = layout.range_max;
    if (layout.count <= 0 || stride < 1 || first < 0 || !fmath::isfinite(layout.angle_min) ||
        !fmath::isfinite(layout.angle_increment) || !fmath::isfinite(layout.range_min) ||
        !fmath::isfinite(layout.range_max) || !(layout.range_max > layout.range_min) || ranges == nullptr)
      return ScanStatus::bad_layout;
    for (std::int32_t k = 0; k < layout.count; ++k) {
      if (k < first || (k - first) % stride != 0) {
        ++counters_.skipped_stride;
        continue;
      }
      float z = ranges[k];
      if (z > 0.0f && !fmath::isfinite(z)) z = layout.range_max;  // +inf: no return (REP 117)
      if (!fmath::isfinite(z)) {
        ++counters_.rejected_nonfinite;
        continue;
      }
      if (z < layout.range_min) {
        ++counters_.rejected_below_min;
        continue;
      }
      if (count_ >= capacity_) {
        count_ = 0;
        counters_.kept = 0;
        return ScanStatus::too_many_beams;
      }
      const bool is_max = z >= layout.range_max;
      float s = 0.0f, c = 0.0f;
      fmath::sincos(layout.angle_min + static_cast<float>(k) * layout.angle_increment, s, c);
      range_[count_] = is_max ? layout.range_max : z;
      ux_[count_] = c;
      uy_[count_] = s;
      is_max_[count_] = is_max ? 1u : 0u;
      ++count_;
      if (is_max) ++counters_.max_readings;
    }
    counters_.kept = count_;
    return count_ > 0 ? ScanStatus::ok : ScanStatus::no_beams;
  }

  ScanBeams beams() const { return {range_, ux_, uy_, is_max_, count_, range_max_}; }
  const ScanCounters& counters() const { return counters_; }

 protected:
  PreparedScanBuffer(float* range, float* ux, float* uy, std::uint8_t* is_max, std::int32_t capacity)
      : range_(range), ux_(ux), uy_(uy), is_max_(is_max), capacity_(capacity) {}
  ~PreparedScanBuffer() = default;

 private:
  float* range_;
  float* ux_;
  float* uy_;
  std::uint8_t* is_max_;
  std::int32_t capacity_;
  std::int32_t count_ = 0;
  float range_max_ = 0.0f;
  ScanCounters counters_{};
};

// K_max kept beams: 13 bytes each.
template <std::int32_t KMax>
class PreparedScan final : public PreparedScanBuffer {
  static_assert(KMax > 0, "capacity must be positive");

 public:
  static constexpr std::int32_t kCapacity = KMax;
  PreparedScan() : PreparedScanBuffer(range_, ux_, uy_, is_max_, KMax) {}

 private:
  static constexpr std::uint32_t kN = static_cast<std::uint32_t>(KMax);
  float range_[kN];
  float ux_[kN];
  float uy_[kN];
  std::uint8_t is_max_[kN];
};

}  // namespace est
